#pragma once
// One simulated wrist: a loaded model and its own mjData, with the operations the experiments need in the paper's
// terms (pressures in kPa at the edge, wrist angles with flexion and ulnar deviation positive). One WristSim per
// thread; several may share a Model.

#include <array>
#include <vector>

#include "physics/relaxed_wrist.h"
#include "physics/torque_geometry.h"
#include "sim/device.h"
#include "sim/model.h"

namespace softwrist::sim {

class WristSim {
 public:
  // Shares `model`, or, where a muscle's wrist surface is not a circle (model_builder.h kWrapSurfaceNumeric), copies
  // it: its wrap cylinders move with the wrist.
  explicit WristSim(const Model& model);

  // Back to the neutral wrist at rest, all pressures zero, time zero.
  void reset();
  // Commanded pressures [kPa] of flexor, extensor, ulnar, radial (the regulators follow with their lag).
  void command_pressures_kpa(const std::array<double, 4>& pressures_kpa);
  // Puts the regulated pressures [kPa] at these, commanded alike and a second-order regulator at rest, so that they
  // hold until changed: a replay driven by measured pressures.
  void set_regulated_pressures_kpa(const std::array<double, 4>& pressures_kpa);
  // Advances `duration` [s] of free motion. Throws std::runtime_error when MuJoCo finds the state unstable (it would
  // reset it and go on).
  void run(double duration);
  // Advances `duration` [s] with the wrist held at (fe, ur) [rad], as on the torque rig: the regulators fill the
  // muscles while the joints stay put.
  void run_held(double duration, double fe, double ur);
  // Puts the wrist at rest at (fe, ur) [rad] with the regulators at `pressures_kpa` (commanded and regulated alike),
  // and computes the state there without advancing time: a pose to draw or to inspect.
  void set_pose(double fe, double ur, const std::array<double, 4>& pressures_kpa);

  double time() const { return data_->time; }
  double angle(physics::WristAxis joint) const;     // [rad]
  double velocity(physics::WristAxis joint) const;  // [rad/s]
  double regulated_pressure_kpa(MuscleIndex muscle) const { return data_->act[muscle]; }
  // The torque one muscle applies about its joint, positive in its own direction [N m] (its share of
  // qfrc_actuator: force times moment arm).
  double muscle_torque(MuscleIndex muscle) const;

  const mjModel* model() const { return model_.get(); }

  // A non-circular wrist surface: its muscle, its geometry, and its cylinder's and side site's ids.
  struct MovingSurface {
    MuscleIndex muscle{};
    physics::Placement placement;
    double wrist_radius = 0.0;
    physics::WrapSurface surface;
    physics::PlacementGeometry geometry;  // of the three above, validated once
    int geom = -1, side_site = -1;
  };
  mjData* data() { return data_.get(); }

 private:
  void hold(double fe, double ur);
  // Puts the relaxed wrist's torque beyond MuJoCo's linear joint stiffness, its asymmetry and its stiffening towards
  // the joint limits (model_builder.h), into qfrc_applied, at the state the next step starts from.
  void apply_relaxed_wrist_beyond_linear();
  void step();
  // Each non-circular wrist surface's equivalent circle at the joints' present angles (model_builder.h).
  void place_wrap_surfaces();
  void forward();  // mj_forward at the present state (or a hair away: below), the surfaces placed
  // Runs `evaluate` (mj_forward, mj_step1) at the present state, or a hair away where a tendon grazes its wrap
  // cylinder and MuJoCo 2.2.2 would give it a NaN length. Throws std::runtime_error naming the tendon where no
  // offset up to 1e-6 rad helps.
  void evaluate_clear_of_grazing_wraps(void (*evaluate)(const mjModel*, mjData*));

  std::vector<MovingSurface> moving_surfaces_;
  Model model_;  // shared, or this simulation's own copy where surfaces move
  Data data_;
  std::array<int, 2> qpos_address_{};  // FE, UR
  std::array<int, 2> dof_address_{};
  std::array<int, 4> pressure_rate_actuator_{};          // a second-order regulator's companions (act ids), or -1
  physics::LimitStiffening limit_stiffening_;            // none unless the model carries kLimitStiffeningNumeric
  std::array<double, 2> stiffness_asymmetry_{};          // per joint; 0 unless it carries kStiffnessAsymmetryNumeric
  std::array<double, 2> joint_stiffness_{};              // per joint [N m/rad]
  std::array<std::array<double, 2>, 2> joint_limits_{};  // per joint: positive, negative limit [rad]
  std::vector<mjtNum> warm_start_;                       // qacc_warmstart before an evaluation (nv)
};

}  // namespace softwrist::sim
