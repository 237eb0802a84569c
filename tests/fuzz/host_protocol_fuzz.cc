// Fuzz target: the bridge's decoder of what the device sends (bridge/host_protocol.h), fed a byte stream through
// the line assembler as BridgePlant feeds it. Whatever arrives, the decoder passes on only well-formed, plausible,
// in-sequence packets, and the limits the host then applies are never looser than its own.

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "bridge/host_protocol.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softwrist;
  bridge::HostProtocol protocol;
  wire::LineAssembler lines;
  const wire::SafetyLimits host;  // the bridge's defaults
  for (std::size_t i = 0; i < size; ++i) {
    if (!lines.push(static_cast<char>(data[i]))) continue;
    FUZZ_CHECK(lines.length() <= wire::kMaxLine);
    switch (protocol.handle_line(lines.line(), lines.length())) {
      case bridge::DeviceLine::kData: {
        const bridge::DeviceData& d = protocol.data();
        FUZZ_CHECK(std::abs(d.fe_cdeg) <= 18000 && std::abs(d.ur_cdeg) <= 18000);
        FUZZ_CHECK(d.flags >= 0 && d.flags < 64);
        for (int m = 0; m < 4; ++m) FUZZ_CHECK(d.measured_dkpa[m] >= -100 && d.measured_dkpa[m] <= 100000);
        break;
      }
      case bridge::DeviceLine::kAnswer: {
        // BridgePlant applies the stricter of its own limits and the announced ones.
        const wire::SafetyLimits announced = protocol.device().limits;
        const std::int32_t max_dkpa = announced.max_dkpa < host.max_dkpa ? announced.max_dkpa : host.max_dkpa;
        FUZZ_CHECK(max_dkpa <= host.max_dkpa);
        break;
      }
      default:
        break;
    }
  }
  return 0;
}
