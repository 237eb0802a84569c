// Fuzz target: the device's decoder of what the host sends (bridge/device_protocol.h, the firmware's and the
// emulator's code), fed a byte stream through the line assembler with the clock advancing between bytes, and the
// safety gate updated as the firmware updates it. Whatever arrives, the regulators are never given more than the
// pressure limit or less than zero, never rise faster than the rate limit, are vented after an emergency stop,
// and are vented once no valid command came within the timeout.

#include <cstddef>
#include <cstdint>

#include "bridge/device_protocol.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softwrist;
  const wire::SafetyLimits limits;
  wire::SafetyGate gate(limits);
  wire::DeviceProtocol protocol(&gate);
  wire::LineAssembler lines;
  std::uint32_t now_ms = 0;
  std::uint32_t last_command_ms = 0;
  bool commanded = false;
  std::int32_t previous[4] = {0, 0, 0, 0};
  std::uint32_t previous_ms = 0;
  for (std::size_t i = 0; i < size; ++i) {
    // A byte takes ~0.09 ms at 115200 baud; every 8th byte the firmware's loop runs (1 ms). Bytes 0xF0..0xFF also
    // stand for a pause (the host quiet) of up to 64 ms, so that the timeout is reached too.
    if (data[i] >= 0xF0) now_ms += 4u * (data[i] - 0xEFu);
    if (i % 8 == 0) ++now_ms;
    if (lines.push(static_cast<char>(data[i]))) {
      wire::Packet reply;
      bool has_reply = false;
      const char type = protocol.handle_line(lines.line(), lines.length(), now_ms, &reply, &has_reply);
      if (has_reply) {
        char buffer[wire::kMaxLine + 2];
        FUZZ_CHECK(wire::format_packet(reply, buffer, sizeof buffer) > 0, "reply %c", reply.type);
      }
      if (type == wire::kSetPacket) {
        last_command_ms = now_ms;
        commanded = true;
      }
      if (type == wire::kHelloPacket) commanded = false;
      if (type == wire::kStopPacket) {
        std::int32_t output[4];
        gate.update(now_ms, output);
        for (int m = 0; m < 4; ++m) FUZZ_CHECK(output[m] == 0, "not vented after an emergency stop");
      }
    }
    std::int32_t output[4];
    gate.update(now_ms, output);
    for (int m = 0; m < 4; ++m) {
      FUZZ_CHECK(output[m] >= 0 && output[m] <= limits.max_dkpa, "muscle %d: %d dkPa", m, output[m]);
      const std::int64_t rise = static_cast<std::int64_t>(limits.rate_dkpa_s) * (now_ms - previous_ms) / 1000;
      FUZZ_CHECK(output[m] - previous[m] <= rise, "muscle %d rose %d dkPa in %u ms", m, output[m] - previous[m],
                 now_ms - previous_ms);
      if (commanded && now_ms - last_command_ms > limits.timeout_ms)
        FUZZ_CHECK(output[m] == 0, "not vented on timeout");
      previous[m] = output[m];
    }
    previous_ms = now_ms;
  }
  return 0;
}
