#include "sim/wrist_sim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "fpam_config.h"
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

// The non-circular wrist surfaces a model carries (model_builder.h kWrapSurfaceNumeric).
std::vector<WristSim::MovingSurface> moving_surfaces(const mjModel* model) {
  std::vector<WristSim::MovingSurface> surfaces;
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    const std::string name = kMuscleNames[i];
    const int numeric = mj_name2id(model, mjOBJ_NUMERIC, (kWrapSurfaceNumeric + name).c_str());
    if (numeric < 0) continue;
    if (model->numeric_size[numeric] != 8) {
      throw std::runtime_error("wrist model: custom numeric '" + (kWrapSurfaceNumeric + name) +
                               "' must hold 8 values (d1 w1 d2 w2 r_w x y aspect)");
    }
    const mjtNum* v = model->numeric_data + model->numeric_adr[numeric];
    const physics::Placement placement{v[0], v[1], v[2], v[3]};
    const physics::WrapSurface surface{v[5], v[6], v[7]};
    std::optional<physics::PlacementGeometry> geometry;
    try {
      geometry.emplace(placement, v[4], surface);
    } catch (const std::exception& e) {
      throw std::runtime_error("wrist model: custom numeric '" + (kWrapSurfaceNumeric + name) + "': " + e.what());
    }
    const WristSim::MovingSurface s{.muscle = static_cast<MuscleIndex>(i),
                                    .placement = placement,
                                    .wrist_radius = v[4],
                                    .surface = surface,
                                    .geometry = *geometry,
                                    .geom = mj_name2id(model, mjOBJ_GEOM, (name + "_wrap").c_str()),
                                    .side_site = mj_name2id(model, mjOBJ_SITE, (name + "_side").c_str())};
    if (s.geom < 0 || s.side_site < 0) throw std::runtime_error("wrist model: no wrap cylinder for '" + name + "'");
    surfaces.push_back(s);
  }
  return surfaces;
}

[[noreturn]] void fail_numeric(const char* name, const std::string& problem) {
  throw std::runtime_error(std::string("wrist model: custom numeric '") + name + "' " + problem);
}

// The two values of the model's custom <numeric> `name` (model_builder.h), or none where it carries none; `what` names
// them for the error where it holds another number of values.
std::optional<std::array<double, 2>> numeric_pair(const mjModel* model, const char* name, const char* what) {
  const int numeric = mj_name2id(model, mjOBJ_NUMERIC, name);
  if (numeric < 0) return std::nullopt;
  if (model->numeric_size[numeric] != 2) fail_numeric(name, std::string("must hold 2 values (") + what + ")");
  const mjtNum* values = model->numeric_data + model->numeric_adr[numeric];
  return std::array<double, 2>{values[0], values[1]};
}

}  // namespace

WristSim::WristSim(const Model& model)
    : moving_surfaces_(moving_surfaces(model.get())),
      model_(moving_surfaces_.empty() ? model : model.Copy()),
      data_(make_data(model_)),
      warm_start_(static_cast<std::size_t>(model_->nv)) {
  const char* names[2] = {"wrist_fe", "wrist_ur"};
  for (int j = 0; j < 2; ++j) {
    const int joint = model.id(mjOBJ_JOINT, names[j]);
    qpos_address_[j] = model->jnt_qposadr[joint];
    dof_address_[j] = model->jnt_dofadr[joint];
    joint_limits_[j] = {model->jnt_range[2 * joint + 1], -model->jnt_range[2 * joint]};
    joint_stiffness_[j] = model->jnt_stiffness[joint];
  }
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    const std::string rate = kMuscleNames[i] + std::string(plugin::FpamConfig::kPressureRateSuffix);
    pressure_rate_actuator_[i] = mj_name2id(model.get(), mjOBJ_ACTUATOR, rate.c_str());
  }
  if (const auto values = numeric_pair(model.get(), kLimitStiffeningNumeric, "torque [N m], e-folding angle [rad]")) {
    limit_stiffening_ = {.torque = (*values)[0], .angle_scale = (*values)[1]};
    if (!(limit_stiffening_.torque >= 0.0) || !(limit_stiffening_.angle_scale > 0.0))
      fail_numeric(kLimitStiffeningNumeric, "needs a torque >= 0 and an e-folding angle > 0");
  }
  if (const auto values =
          numeric_pair(model.get(), kStiffnessAsymmetryNumeric, "flexion/extension, ulnar/radial asymmetry")) {
    stiffness_asymmetry_ = *values;
    for (const double a : stiffness_asymmetry_) {
      if (!(std::abs(a) <= physics::kMaxStiffnessAsymmetry))
        fail_numeric(kStiffnessAsymmetryNumeric, "needs each within 0.9");
    }
  }
  // Four fPAMs and after them four companions for each of: the fabric's hysteresis, a second-order regulator
  // (sim/model_builder.cc).
  if (model->nu != model->na || (model->nu != 4 && model->nu != 8 && model->nu != 12))
    throw std::runtime_error(
        "wrist model: expected four fPAM actuators (and four companions each for hysteresis and a second-order "
        "regulator)");
  // The compiler marks a geom or site placed at its body's origin as sharing the body's frame, and MuJoCo then
  // ignores its position: the moving surfaces' cylinders and side sites move (in this simulation's own copy).
  for (const MovingSurface& s : moving_surfaces_) {
    model_.get_mutable()->geom_sameframe[s.geom] = 0;
    model_.get_mutable()->site_sameframe[s.side_site] = 0;
  }
  reset();
}

void WristSim::reset() {
  mj_resetData(model_.get(), data_.get());
  forward();
}

void WristSim::forward() {
  place_wrap_surfaces();
  evaluate_clear_of_grazing_wraps(mj_forward);
}

// MuJoCo 2.2.2 measures a tendon's arc on a wrap cylinder with an unclamped acos (length_circle in
// engine_util_misc.c): where the straight path just grazes the cylinder its two tangent points coincide, rounding can
// put their cosine a last bit above 1, and the tendon's length and wrap points turn NaN (and, in the next step, the
// accelerations: seed 14's elliptical_section, an idle extensor grazing its cylinder while the ulnar muscle held the
// wrist still). The wrapped length is continuous there (an arc of zero), so the positions are evaluated a hair away
// instead, the joints' angles offset by 1e-10 rad and up to 1e-6 (a hand site moves 1e-11 m), then put back; the
// solver's warm start too, which a NaN evaluation by mj_forward would leave NaN.
void WristSim::evaluate_clear_of_grazing_wraps(void (*evaluate)(const mjModel*, mjData*)) {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  std::copy_n(d->qacc_warmstart, m->nv, warm_start_.begin());
  evaluate(m, d);
  const auto nan_tendon = [&] {
    return std::find_if(d->ten_length, d->ten_length + m->ntendon, [](mjtNum l) { return !std::isfinite(l); }) -
           d->ten_length;
  };
  if (nan_tendon() == m->ntendon) return;
  const std::array<double, 2> angles{d->qpos[qpos_address_[0]], d->qpos[qpos_address_[1]]};
  for (const double offset : {1e-10, 1e-9, 1e-8, 1e-7, 1e-6}) {
    for (int j = 0; j < 2; ++j) d->qpos[qpos_address_[j]] = angles[j] + offset;
    std::copy(warm_start_.begin(), warm_start_.end(), d->qacc_warmstart);
    evaluate(m, d);
    if (nan_tendon() == m->ntendon) break;
  }
  for (int j = 0; j < 2; ++j) d->qpos[qpos_address_[j]] = angles[j];
  if (const auto tendon = nan_tendon(); tendon < m->ntendon) {
    const char* name = mj_id2name(m, mjOBJ_TENDON, static_cast<int>(tendon));
    throw std::runtime_error(fmt::format(
        "the simulation cannot go on: tendon '{}' has no finite length at flexion {:.6g} rad, ulnar deviation {:.6g} "
        "rad, nor within 1e-6 rad of it (MuJoCo's wrap around its cylinder)",
        name != nullptr ? name : "?", angles[0], angles[1]));
  }
}

// The 2D law's equivalent circle (torque_geometry.h) at the muscle's joint angle, in its plane: the cylinder's centre
// and radius, and its side site 2 r from the centre on the muscle's side, as model_builder puts them.
void WristSim::place_wrap_surfaces() {
  if (moving_surfaces_.empty()) return;
  mjModel* m = model_.get_mutable();
  for (const MovingSurface& s : moving_surfaces_) {
    const double angle =
        physics::direction_of(s.muscle) * data_->qpos[qpos_address_[static_cast<int>(physics::axis_of(s.muscle))]];
    const double clamped = std::clamp(angle, -std::numbers::pi, std::numbers::pi);
    const physics::MusclePath path = s.geometry.at(clamped);
    const physics::EquivalentCircle c =
        physics::equivalent_circle(s.placement, s.wrist_radius, s.surface, clamped, path);
    const std::array<double, 3>& side = kMuscleSides[s.muscle];
    for (int k = 0; k < 3; ++k) {
      m->geom_pos[3 * s.geom + k] = k == 0 ? c.x : side[k] * c.y;
      m->site_pos[3 * s.side_site + k] = k == 0 ? c.x : side[k] * (c.y + 2.0 * c.radius);
    }
    m->geom_size[3 * s.geom] = c.radius;
  }
}

void WristSim::command_pressures_kpa(const std::array<double, 4>& pressures_kpa) {
  for (int i = 0; i < 4; ++i) data_->ctrl[i] = pressures_kpa[static_cast<std::size_t>(i)];
}

void WristSim::apply_relaxed_wrist_beyond_linear() {
  if (limit_stiffening_.torque == 0.0 && stiffness_asymmetry_[0] == 0.0 && stiffness_asymmetry_[1] == 0.0) return;
  for (int j = 0; j < 2; ++j) {
    // The joints' axes are set so that flexion and ulnar deviation are positive (model_builder.h).
    const double angle = data_->qpos[qpos_address_[j]];
    data_->qfrc_applied[dof_address_[j]] =
        physics::stiffness_asymmetry_torque(joint_stiffness_[j], stiffness_asymmetry_[j], angle) +
        physics::limit_stiffening_torque(limit_stiffening_, joint_limits_[j][0], joint_limits_[j][1], angle);
  }
}

// Explicit in the stiffening (evaluated at the step's start): stable while its stiffness near a limit, A/s, keeps
// sqrt((A/s)/I) dt well below 1 (A = 5 N m, s = 8 deg, I = 0.0034 kg m^2: 0.07 at 1 ms).
void WristSim::step() {
  apply_relaxed_wrist_beyond_linear();
  place_wrap_surfaces();
  if (model_->opt.integrator == mjINT_RK4) {
    mj_step(model_.get(), data_.get());  // RK4 evaluates the positions inside its stages: no check between halves
  } else {
    // mj_step as its two halves (the same computation for Euler and implicit), the positions checked in between.
    evaluate_clear_of_grazing_wraps(mj_step1);
    mj_step2(model_.get(), data_.get());
  }
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
  forward();
}

void WristSim::set_regulated_pressures_kpa(const std::array<double, 4>& pressures_kpa) {
  for (int i = 0; i < 4; ++i) data_->ctrl[i] = data_->act[i] = pressures_kpa[static_cast<std::size_t>(i)];
  for (const int rate : pressure_rate_actuator_) {
    if (rate >= 0) data_->act[rate] = 0.0;
  }
}

void WristSim::set_pose(double fe, double ur, const std::array<double, 4>& pressures_kpa) {
  hold(fe, ur);
  set_regulated_pressures_kpa(pressures_kpa);
  apply_relaxed_wrist_beyond_linear();
  forward();
}

double WristSim::angle(physics::WristAxis joint) const { return data_->qpos[qpos_address_[static_cast<int>(joint)]]; }
double WristSim::velocity(physics::WristAxis joint) const { return data_->qvel[dof_address_[static_cast<int>(joint)]]; }

double WristSim::muscle_torque(MuscleIndex muscle) const {
  const int dof = dof_address_[static_cast<int>(physics::axis_of(muscle))];
  return physics::direction_of(muscle) * data_->actuator_force[muscle] *
         data_->actuator_moment[muscle * model_->nv + dof];
}

}  // namespace softwrist::sim
