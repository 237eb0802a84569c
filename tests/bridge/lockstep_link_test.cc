// The lock-step rig (bridge_apps/lockstep_link.h): the line's rate, the host's clock, the cable, the faults on the
// line. (The bridge and the emulator on it: bridge_emulator_test.cc.)

#include "bridge_apps/lockstep_link.h"

#include <memory>
#include <optional>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bridge/wire_format.h"
#include "support/emulator_test_support.h"

namespace softwrist::bridge {
namespace {

using ::testing::HasSubstr;
using testing::nominal_emulator_config;

// The line carries 11.52 bytes per millisecond (115200 baud, 8N1), and the host's clock is the rig's: reads that
// wait let the rig's time pass, reads that do not wait take none.
TEST(LockstepLink, TheLineCarriesBytesAtTheUartsRateAndTheHostsClockIsTheRigs) {
  DeviceEmulator emulator(nominal_emulator_config());
  LockstepLink rig(emulator);
  const std::unique_ptr<Link> host = rig.open_host();
  EXPECT_THAT([&] { rig.open_host(); }, ::testing::ThrowsMessage<std::logic_error>(HasSubstr("open already")));
  char buffer[256];
  std::size_t total = 0, most = 0, busy_ms = 0;
  for (int k = 0; k < 1000; ++k) {  // one second of the device's 100 Hz data packets, a millisecond at a time
    const std::uint32_t before = rig.now_ms();
    const std::size_t n = host->read_some(buffer, sizeof buffer, 1);
    EXPECT_EQ(rig.now_ms(), before + 1);
    EXPECT_EQ(host->read_some(buffer, sizeof buffer, 0), 0u);  // all read; a read that does not wait takes no time
    EXPECT_EQ(rig.now_ms(), before + 1);
    total += n;
    most = std::max(most, n);
    busy_ms += n > 0 ? 1 : 0;
  }
  EXPECT_LE(most, 12u);          // the line's rate
  EXPECT_GE(most, 11u);          // reached while a packet is on the line
  EXPECT_GE(total, 100u * 30u);  // a hundred packets of 30+ bytes
  EXPECT_GE(static_cast<double>(busy_ms), static_cast<double>(total) / 11.52 - 1.0);  // each byte its time
}

TEST(LockstepLink, ALinkCutIsGoneForTheHostAndTheCableStaysOut) {
  EmulatorConfig config = nominal_emulator_config();
  config.faults.link_cut_at_s = 0.0;  // at the first hello
  DeviceEmulator emulator(config);
  LockstepLink rig(emulator);
  const std::unique_ptr<Link> host = rig.open_host();
  wire::Packet p{};  // a hello: the device's fault schedule starts at the first one
  p.type = wire::kHelloPacket;
  p.count = 1;
  p.fields[0] = wire::kProtocolVersion;
  char line[wire::kMaxLine + 2];
  host->write_all(line, wire::format_packet(p, line, sizeof line));
  char buffer[64];
  EXPECT_THAT(
      [&] {
        for (int k = 0; k < 50; ++k) host->read_some(buffer, sizeof buffer, 1);
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("the link is gone")));
  EXPECT_FALSE(rig.cable_in());
  EXPECT_THAT([&] { rig.open_host(); }, ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("the cable is out")));
}

// Faults on the line act on the bytes in transit: a stall loses them, noise garbles them, a cut ends the host's
// end and a new one opens once the cable is back; the schedule is the same for the same seed.
TEST(LockstepLink, FaultsOnTheLineFollowTheirScheduleAndActOnTheBytes) {
  DeviceEmulator emulator(nominal_emulator_config());
  LockstepLink rig(emulator, {.faults = LineFaultOptions{.mean_interval_s = 0.2, .seed = 7}});
  std::unique_ptr<Link> host = rig.open_host();
  char buffer[512];
  long received = 0, while_blocked = 0, cuts_seen = 0;
  while (rig.now_ms() < 20000) {
    std::optional<InjectedFault> active;
    if (!rig.faults().empty()) active = rig.faults().back();
    try {
      if (!host) {
        if (!rig.cable_in()) {
          rig.run_for_ms(1);
          continue;
        }
        host = rig.open_host();
      }
      const std::size_t n = host->read_some(buffer, sizeof buffer, 1);
      received += static_cast<long>(n);
      const bool blocked = active && rig.now_s() < active->onset_s + active->duration_s &&
                           rig.now_s() > active->onset_s + 0.002 && active->kind == LinkFault::kStall;
      if (blocked) while_blocked += static_cast<long>(n);
    } catch (const std::runtime_error& e) {  // a cut that began while the host waited
      EXPECT_THAT(e.what(), HasSubstr("the link is gone"));
      EXPECT_EQ(rig.faults().back().kind, LinkFault::kLinkCut);
      host.reset();
      ++cuts_seen;
    }
  }
  ASSERT_GE(rig.faults().size(), 20u);
  long cuts = 0;
  for (const InjectedFault& f : rig.faults()) {
    cuts += f.kind == LinkFault::kLinkCut ? 1 : 0;
    EXPECT_GE(f.duration_s, 0.06);
    EXPECT_LE(f.duration_s, 0.5);
  }
  EXPECT_EQ(cuts_seen, cuts);
  EXPECT_EQ(while_blocked, 0);  // a stall lets nothing through
  EXPECT_GT(received, 20000);   // 20 s of 100 Hz data packets (~5 kB/s), less the faults (about half the time)

  DeviceEmulator again_emulator(nominal_emulator_config());
  LockstepLink again(again_emulator, {.faults = LineFaultOptions{.mean_interval_s = 0.2, .seed = 7}});
  again.run_for_ms(20000);
  ASSERT_EQ(again.faults().size(), rig.faults().size());
  for (std::size_t i = 0; i < rig.faults().size(); ++i) {
    EXPECT_EQ(again.faults()[i].kind, rig.faults()[i].kind);
    EXPECT_DOUBLE_EQ(again.faults()[i].onset_s, rig.faults()[i].onset_s);
  }
}

}  // namespace
}  // namespace softwrist::bridge
