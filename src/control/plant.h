#pragma once
// What a controller sees of the exosuit (Section Control system): four commanded pressures out, two wrist angles
// from the IMU pair in, and time. The simulation (sim/simulated_plant.h) and the hardware bridge
// (bridge/bridge_plant.h) implement it; a controller written against it runs on either unchanged, and both keep the
// same contract (tests/bridge/plant_contract_test.cc). Units at this edge are the paper's: kPa and degrees (flexion
// and ulnar deviation positive), seconds.

#include <array>
#include <stdexcept>

#include "physics/exosuit_layout.h"

namespace softwrist::control {

// Flexor, extensor, ulnar, radial (the order of the model's actuators).
using Pressures = std::array<double, 4>;
using physics::kMuscleNames;

struct WristAngles {
  double fe_deg = 0.0;  // flexion positive
  double ur_deg = 0.0;  // ulnar deviation positive
};

// A desired wrist motion at one instant: the angles and how fast they change (0 across a step's jump).
struct Reference {
  WristAngles angles;
  WristAngles rate_deg_s;
};

struct ImuReading {
  WristAngles angles;
  double time_s = 0.0;  // when the IMUs sampled it
  bool valid = false;   // false until the first sample, or when the IMUs report an error
};

// A command the plant refuses, or a fault of the plant itself (the bridge's BridgeFault). The plant has vented,
// every muscle commanded to 0 kPa, before it throws; the message names the cause.
class PlantFault : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Plant {
 public:
  virtual ~Plant() = default;
  // Sets the regulators' commanded pressures [kPa]. Each must be finite and within [0, max_pressure_kpa()]: anything
  // else comes from a broken controller, so the plant vents every muscle and throws PlantFault naming the muscle and
  // the value, on every plant alike. Saturating a controller's output is the caller's choice (run_tracking's
  // TrackingOptions::OutOfRange::kClamp), never the plant's.
  virtual void command_pressures_kpa(const Pressures& pressures) = 0;
  // The latest IMU sample (100 Hz on the paper's device).
  virtual ImuReading read_angles() = 0;
  virtual double time_s() const = 0;
  // Returns at time `t` [s]: the simulation steps to it, the hardware waits for it.
  virtual void wait_until(double t) = 0;
  // The regulators' range [kPa].
  virtual double max_pressure_kpa() const = 0;
};

}  // namespace softwrist::control
