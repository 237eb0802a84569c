// Fuzz target: the placement file (sim::parse_device, docs/placement-file.md). A file is either rejected with an
// error naming the file and the field, or accepted; an accepted one writes back to itself and gives finite forces
// and torques at every pressure of its regulators over the wrist's range.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "fuzz_check.h"
#include "physics/units.h"
#include "sim/device.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softwrist;
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::optional<sim::DeviceDescription> parsed;
  try {
    parsed = sim::parse_device(text, "fuzz.json");
  } catch (const std::runtime_error& e) {
    fuzz::check_names_source(e.what(), "fuzz.json");
    return 0;
  }
  const sim::DeviceDescription& device = *parsed;
  const std::string written = sim::device_to_json(device);
  FUZZ_CHECK(sim::device_to_json(sim::parse_device(written, "written.json")) == written, "%s", written.c_str());
  for (int i = 0; i < 4; ++i) {
    const physics::Muscle muscle = device.muscle(i);
    for (double fraction : {0.0, 0.5, 1.0}) {
      for (double angle_deg = -90.0; angle_deg <= 90.0; angle_deg += 30.0) {
        const auto state =
            physics::muscle_state(muscle, units::deg_to_rad(angle_deg), fraction * device.regulator.max_pressure);
        FUZZ_CHECK(std::isfinite(state.force) && std::isfinite(state.torque) && state.force >= 0.0,
                   "muscle %d at %g deg, %g of the maximum pressure: force %g, torque %g", i, angle_deg, fraction,
                   state.force, state.torque);
      }
    }
  }
  return 0;
}
