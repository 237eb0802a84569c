// Fuzz target: the placement file (sim::parse_device, docs/placement-file.md). A file is either rejected with an
// error naming the file and the field, or accepted; an accepted one writes back to itself and gives finite forces
// and torques at every pressure of its regulators over the wrist's range.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_check.h"
#include "physics/units.h"
#include "sim/device.h"

namespace {

bool same_to_rounding(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    return std::abs(x - y) <= 1e-12 * std::max({1.0, std::abs(x), std::abs(y)});
  }
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key()) || !same_to_rounding(it.value(), b.at(it.key()))) return false;
    }
    return true;
  }
  if (a.is_array()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!same_to_rounding(a[i], b[i])) return false;
    }
    return true;
  }
  return a == b;
}

}  // namespace

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
  // Written back, it reads to the same description, to within the rounding of the cm <-> m conversions (found by
  // this target: 5.6004000000000005 cm came back one ulp off).
  const std::string written = sim::device_to_json(device);
  const std::string rewritten = sim::device_to_json(sim::parse_device(written, "written.json"));
  FUZZ_CHECK(same_to_rounding(nlohmann::json::parse(written), nlohmann::json::parse(rewritten)), "%s\n%s",
             written.c_str(), rewritten.c_str());
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
