#pragma once
// The exosuit's vocabulary, in one place (Section Design Overview, Section Exosuit Prototype): its four muscles in
// the order of the model's tendons, actuators and every four-pressure array; the two wrist axes they move; the
// regulators' pressure range. Every layer (control, sim, bridge, diagnosis) names muscles, axes and the limit from
// here.

#include <array>

namespace softwrist::physics {

// The four muscles, in the order of the model's tendons and actuators and of every four-pressure array.
enum MuscleIndex { kFlexor = 0, kExtensor = 1, kUlnar = 2, kRadial = 3 };
inline constexpr std::array<const char*, 4> kMuscleNames = {"flexor", "extensor", "ulnar", "radial"};

// Sign convention (antagonistic_pair.h): flexion and ulnar deviation positive.
enum class WristAxis { kFlexionExtension, kUlnarRadial };

// The axis a muscle moves, and the sign of its own direction on it: flexor +FE, extensor -FE, ulnar +UR, radial -UR.
constexpr WristAxis axis_of(MuscleIndex muscle) {
  return muscle == kFlexor || muscle == kExtensor ? WristAxis::kFlexionExtension : WristAxis::kUlnarRadial;
}
constexpr double direction_of(MuscleIndex muscle) { return muscle == kFlexor || muscle == kUlnar ? 1.0 : -1.0; }

// Section Exosuit Prototype: the regulators (QB3, Proportion-Air) hold 0-137 kPa.
inline constexpr double kRegulatorMaxPressure = 137e3;     // [Pa]
inline constexpr double kRegulatorMaxPressureKpa = 137.0;  // the same at the kPa edges (configs, commands, the CLI)

}  // namespace softwrist::physics
