#include "sim/wrist_sim.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "sim/model_builder.h"

namespace softwrist::sim {
namespace {

// MuJoCo resets the state when an acceleration, velocity or position turns NaN, Inf or huge, warns, and carries on
// from there: every result after that would be silently wrong, so the simulation stops with the reason instead.
void check_stable(const mjData* d) {
  for (const auto& [warning, what] :
       {std::pair{mjWARN_BADQACC, "acceleration"}, {mjWARN_BADQVEL, "velocity"}, {mjWARN_BADQPOS, "position"}}) {
    if (d->warning[warning].number > 0) {
      throw std::runtime_error(std::string("the simulation became unstable: NaN, Inf or a huge value in a joint's ") +
                               what + " (a device too stiff or too strong for the model's time step?)");
    }
  }
}

}  // namespace

WristSim::WristSim(const Model& model) : model_(model), data_(make_data(model)) {
  const char* names[2] = {"wrist_fe", "wrist_ur"};
  for (int j = 0; j < 2; ++j) {
    const int joint = model.id(mjOBJ_JOINT, names[j]);
    qpos_address_[j] = model->jnt_qposadr[joint];
    dof_address_[j] = model->jnt_dofadr[joint];
    joint_limits_[j] = {model->jnt_range[2 * joint + 1], -model->jnt_range[2 * joint]};
  }
  const int numeric = mj_name2id(model.get(), mjOBJ_NUMERIC, kLimitStiffeningNumeric);
  if (numeric >= 0) {
    if (model->numeric_size[numeric] != 2) {
      throw std::runtime_error(std::string("wrist model: custom numeric '") + kLimitStiffeningNumeric +
                               "' must hold 2 values (torque [N m], e-folding angle [rad])");
    }
    const mjtNum* values = model->numeric_data + model->numeric_adr[numeric];
    limit_stiffening_ = {.torque = values[0], .angle_scale = values[1]};
    if (!(limit_stiffening_.torque >= 0.0) || !(limit_stiffening_.angle_scale > 0.0)) {
      throw std::runtime_error(std::string("wrist model: custom numeric '") + kLimitStiffeningNumeric +
                               "' needs a torque >= 0 and an e-folding angle > 0");
    }
  }
  // Four fPAMs and, where the fabric has hysteresis, their four branch states after them (sim/model_builder.cc).
  if (model->nu != model->na || (model->nu != 4 && model->nu != 8))
    throw std::runtime_error("wrist model: expected four fPAM actuators (and with hysteresis their four states)");
  reset();
}

void WristSim::reset() {
  mj_resetData(model_.get(), data_.get());
  mj_forward(model_.get(), data_.get());
}

void WristSim::command_pressures_kpa(const std::array<double, 4>& pressures_kpa) {
  for (int i = 0; i < 4; ++i) data_->ctrl[i] = pressures_kpa[static_cast<std::size_t>(i)];
}

void WristSim::apply_limit_stiffening() {
  if (limit_stiffening_.torque == 0.0) return;
  for (int j = 0; j < 2; ++j) {
    // The joints' axes are set so that flexion and ulnar deviation are positive (model_builder.h).
    data_->qfrc_applied[dof_address_[j]] = physics::limit_stiffening_torque(
        limit_stiffening_, joint_limits_[j][0], joint_limits_[j][1], data_->qpos[qpos_address_[j]]);
  }
}

// Explicit in the stiffening (evaluated at the step's start): stable while its stiffness near a limit, A/s, keeps
// sqrt((A/s)/I) dt well below 1 (A = 5 N m, s = 8 deg, I = 0.0034 kg m^2: 0.07 at 1 ms).
void WristSim::step() {
  apply_limit_stiffening();
  mj_step(model_.get(), data_.get());
  check_stable(data_.get());
}

void WristSim::run(double duration) {
  const double end = data_->time + duration - 0.5 * model_->opt.timestep;
  while (data_->time < end) step();
}

void WristSim::hold(double fe, double ur) {
  data_->qpos[qpos_address_[0]] = fe;
  data_->qpos[qpos_address_[1]] = ur;
  data_->qvel[dof_address_[0]] = 0.0;
  data_->qvel[dof_address_[1]] = 0.0;
}

void WristSim::run_held(double duration, double fe, double ur) {
  const double end = data_->time + duration - 0.5 * model_->opt.timestep;
  while (data_->time < end) {
    hold(fe, ur);
    step();
  }
  hold(fe, ur);
  mj_forward(model_.get(), data_.get());
}

void WristSim::set_pose(double fe, double ur, const std::array<double, 4>& pressures_kpa) {
  hold(fe, ur);
  for (int i = 0; i < 4; ++i) data_->ctrl[i] = data_->act[i] = pressures_kpa[static_cast<std::size_t>(i)];
  apply_limit_stiffening();
  mj_forward(model_.get(), data_.get());
}

double WristSim::angle(physics::WristAxis joint) const { return data_->qpos[qpos_address_[static_cast<int>(joint)]]; }
double WristSim::velocity(physics::WristAxis joint) const { return data_->qvel[dof_address_[static_cast<int>(joint)]]; }

double WristSim::muscle_torque(MuscleIndex muscle) const {
  const int dof = dof_address_[static_cast<int>(physics::axis_of(muscle))];
  return physics::direction_of(muscle) * data_->actuator_force[muscle] *
         data_->actuator_moment[muscle * model_->nv + dof];
}

}  // namespace softwrist::sim
