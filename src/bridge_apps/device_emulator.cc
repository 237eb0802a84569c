#include "bridge_apps/device_emulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <random>
#include <thread>

#include <fmt/format.h>

#include "bridge/device_protocol.h"
#include "bridge/pwm_scaling.h"
#include "experiments/simulated_device.h"
#include "io/json_reader.h"
#include "io/text_file.h"
#include "physics/units.h"
#include "sim/simulated_plant.h"

namespace softwrist::bridge {
namespace {

constexpr std::uint32_t kDataPeriodMs = 10;  // 100 Hz, as the firmware

int32_t to_fixed(double value, double scale) { return static_cast<int32_t>(std::lround(value * scale)); }

}  // namespace

EmulatorConfig load_emulator_config(const std::filesystem::path& path) {
  const nlohmann::json json = io::parse_json(io::read_text_file(path), path.string());
  io::JsonReader r(json, path.string(), "");
  if (const std::string format = r.text("format"); format != kEmulatorFormat) {
    r.fail("format", fmt::format("'{}' is not '{}'", format, kEmulatorFormat));
  }
  (void)r.text("description", "");
  EmulatorConfig c;
  const std::filesystem::path model = r.text("model");
  c.model = model.is_absolute() ? model : std::filesystem::absolute(path).parent_path() / model;
  c.gravity = r.boolean("hand_supported", false) ? 0.0 : 9.81;
  const long long seed = r.integer("seed", 1);
  if (seed < 0) r.fail("seed", "must be >= 0");
  c.seed = static_cast<std::uint64_t>(seed);
  if (r.has("effects")) {
    io::JsonReader e = r.child("effects");
    if (e.has("mount_stretch")) {
      io::JsonReader m = e.child("mount_stretch");
      // Placement-file units (docs/placement-file.md): N/cm^2.
      c.effects.mount_stiffness = physics::MountStiffness{.forearm = m.positive("K1_n_per_cm2") * 1e4,
                                                          .hand = m.positive("K2_n_per_cm2") * 1e4};
      m.finish();
    }
    if (e.has("regulator_lag")) {
      io::JsonReader g = e.child("regulator_lag");
      if (g.has("time_constant_s")) c.effects.regulator_time_constant_s = g.positive("time_constant_s");
      c.effects.regulator_dead_time_s = g.non_negative("dead_time_s", 0.0);
      if (c.effects.regulator_dead_time_s > 1.0) g.fail("dead_time_s", "is above 1 s");
      g.finish();
    }
    c.effects.pwm_steps = e.boolean("pwm_steps", true);
    c.effects.pwm_filter_time_constant_s = e.non_negative("pwm_filter_time_constant_s", 0.010);
    if (c.effects.pwm_filter_time_constant_s > 1.0) e.fail("pwm_filter_time_constant_s", "is above 1 s");
    if (e.has("passive_wrist")) {
      io::JsonReader w = e.child("passive_wrist");
      c.effects.wrist_stiffness_scale = w.positive("stiffness_scale", 1.0);
      c.effects.wrist_damping_scale = w.positive("damping_scale", 1.0);
      if (c.effects.wrist_stiffness_scale > 10 || c.effects.wrist_damping_scale > 10) {
        w.fail(c.effects.wrist_stiffness_scale > 10 ? "stiffness_scale" : "damping_scale", "must be within 0..10");
      }
      w.finish();
    }
    if (e.has("imu")) {
      io::JsonReader i = e.child("imu");
      c.effects.imu_noise_std_deg = i.non_negative("noise_std_deg", 0.0);
      c.effects.imu_bias_fe_deg = i.number("bias_fe_deg", 0.0);
      c.effects.imu_bias_ur_deg = i.number("bias_ur_deg", 0.0);
      c.effects.imu_latency_s = i.non_negative("latency_s", 0.0);
      if (c.effects.imu_latency_s > 1.0) i.fail("latency_s", "is above 1 s");
      if (std::abs(c.effects.imu_bias_fe_deg) > 45 || std::abs(c.effects.imu_bias_ur_deg) > 45) {
        i.fail("bias_fe_deg", "biases must be within +-45 deg");
      }
      i.finish();
    }
    e.finish();
  }
  if (r.has("faults")) {
    io::JsonReader f = r.child("faults");
    // A time in seconds after the first hello, or -1 (never) when absent.
    const auto when = [&f](const std::string& key) { return f.has(key) ? f.non_negative(key, 0.0) : -1.0; };
    c.faults.imu_stale_at_s = when("imu_stale_at_s");
    c.faults.garbage_at_s = when("garbage_at_s");
    c.faults.garbage_bytes = static_cast<int>(f.integer("garbage_bytes", c.faults.garbage_bytes));
    if (c.faults.garbage_bytes < 1 || c.faults.garbage_bytes > 100000) f.fail("garbage_bytes", "must be 1..100000");
    c.faults.link_cut_at_s = when("link_cut_at_s");
    f.finish();
  }
  if (r.has("limits")) {
    io::JsonReader l = r.child("limits");
    c.limits.max_dkpa = to_fixed(l.positive("max_kpa", c.limits.max_dkpa / 10.0), 10.0);
    c.limits.rate_dkpa_s = to_fixed(l.positive("rate_kpa_s", c.limits.rate_dkpa_s / 10.0), 10.0);
    const double timeout = l.positive("timeout_ms", c.limits.timeout_ms);
    if (timeout < 1 || timeout > 1000) l.fail("timeout_ms", "must be 1..1000");
    c.limits.timeout_ms = static_cast<uint32_t>(timeout);
    l.finish();
  }
  r.finish();
  return c;
}

sim::DeviceDescription emulated_description(const EmulatorConfig& config) {
  sim::DeviceDescription d = sim::load_device(config.model);
  const EmulatorEffects& fx = config.effects;
  if (fx.mount_stiffness) {
    d.mount_stiffness.forearm = fx.mount_stiffness->forearm;  // the placement's law's shape stays
    d.mount_stiffness.hand = fx.mount_stiffness->hand;
    d.stretch_mode = physics::StretchMode::kSelfConsistent;
  }
  if (fx.regulator_time_constant_s) d.regulator.time_constant = *fx.regulator_time_constant_s;
  d.wrist.stiffness_fe *= fx.wrist_stiffness_scale;
  d.wrist.stiffness_ur *= fx.wrist_stiffness_scale;
  d.wrist.damping_fe *= fx.wrist_damping_scale;
  d.wrist.damping_ur *= fx.wrist_damping_scale;
  return d;
}

// The simulated exosuit behind the emulated firmware.
struct DeviceEmulator::Device {
  explicit Device(const EmulatorConfig& config)
      : simulated(emulated_description(config), sim::ModelOptions{.gravity = config.gravity}),
        plant(simulated.model, units::pa_to_kpa(simulated.description.regulator.max_pressure),
              sim::ImuModel{.period_s = kDataPeriodMs / 1000.0,
                            .noise_std_deg = config.effects.imu_noise_std_deg,
                            .bias_limit_deg = 0.0,
                            .seed = config.seed}) {}

  experiments::SimulatedDevice simulated;
  sim::SimulatedPlant plant;
};

// What the firmware keeps between passes of its loop.
struct DeviceEmulator::Firmware {
  explicit Firmware(const EmulatorConfig& config)
      : gate(config.limits),
        protocol(&gate),
        rng(config.seed ^ 0x5eedULL),
        dead_time_ms(static_cast<std::uint32_t>(std::lround(config.effects.regulator_dead_time_s * 1000.0))),
        latency_ms(static_cast<std::uint32_t>(std::lround(config.effects.imu_latency_s * 1000.0))) {}

  wire::SafetyGate gate;
  wire::DeviceProtocol protocol;
  wire::LineAssembler lines;
  std::deque<char> received;  // from the host, not yet read by the loop
  std::mt19937_64 rng;
  std::uint32_t dead_time_ms, latency_ms;
  std::deque<std::pair<std::uint32_t, std::array<int32_t, 4>>> setpoints;  // for the dead time
  std::deque<std::pair<std::uint32_t, control::WristAngles>> readings;     // for the IMU latency
  std::array<double, 4> filtered_kpa{};                                    // each PWM pin's RC filter [kPa of setpoint]
  std::optional<std::uint32_t> last_output_ms;
  int32_t fe_cdeg = 0, ur_cdeg = 0;
  bool vented = true, imu_stale = false;
  std::optional<std::uint32_t> first_hello_ms;
  std::uint32_t estop_ms = 0, last_command_ms = 0, last_imu_ms = 0;
  bool estop_pending = false, hello_pending = false;
  std::uint32_t next_data = 0;
  bool injected[3] = {false, false, false};
};

DeviceEmulator::DeviceEmulator(const EmulatorConfig& config)
    : config_(config), device_(std::make_unique<Device>(config)), firmware_(std::make_unique<Firmware>(config)) {}

DeviceEmulator::~DeviceEmulator() = default;

EmulatorStats DeviceEmulator::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void DeviceEmulator::receive(const char* data, std::size_t size) {
  firmware_->received.insert(firmware_->received.end(), data, data + size);
}

void DeviceEmulator::write(const char* data, std::size_t size, DeviceUart& uart) {
  if (const std::size_t dropped = uart.write(data, size); dropped > 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.bytes_dropped += static_cast<long>(dropped);
  }
}

void DeviceEmulator::send(const wire::Packet& packet, DeviceUart& uart) {
  char buffer[wire::kMaxLine + 2];
  write(buffer, wire::format_packet(packet, buffer, sizeof buffer), uart);
}

void DeviceEmulator::handle_line(std::uint32_t now, DeviceUart& uart) {
  Firmware& fw = *firmware_;
  wire::Packet reply;
  bool has_reply = false;
  const char type = fw.protocol.handle_line(fw.lines.line(), fw.lines.length(), now, &reply, &has_reply);
  if (has_reply) send(reply, uart);
  if (type != 0 && observer_) {
    wire::Packet accepted;
    wire::parse_line(fw.lines.line(), fw.lines.length(), &accepted);
    observer_(type, accepted.seq);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (type == 0) {
    ++stats_.packets_rejected;
    return;
  }
  ++stats_.packets_accepted;
  if (type == wire::kHelloPacket) {
    // The subject puts the wrist at neutral and holds it there, vented, until the first command: the host zeroes
    // the angles there, as the paper did.
    device_->plant.hold(control::WristAngles{});
    ++stats_.sessions;
    if (!fw.first_hello_ms) fw.first_hello_ms = now;
    fw.hello_pending = true;
    fw.last_command_ms = fw.last_imu_ms = now;
  } else if (type == wire::kSetPacket) {
    device_->plant.hold(std::nullopt);
    fw.last_command_ms = now;
  } else if (type == wire::kStopPacket) {
    fw.estop_pending = true;
    fw.estop_ms = now;
  }
}

void DeviceEmulator::inject_faults(std::uint32_t t, DeviceUart& uart) {
  Firmware& fw = *firmware_;
  const auto due = [&](int k, double at_s) {
    if (fw.injected[k] || at_s < 0.0 || !fw.first_hello_ms ||
        t < *fw.first_hello_ms + static_cast<std::uint32_t>(at_s * 1000.0)) {
      return false;
    }
    fw.injected[k] = true;
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.fault_injected_ms[k] = t;
    return true;
  };
  if (due(0, config_.faults.imu_stale_at_s)) fw.imu_stale = true;
  if (due(1, config_.faults.garbage_at_s)) {
    std::string junk(static_cast<std::size_t>(config_.faults.garbage_bytes), '\0');
    for (char& c : junk) c = static_cast<char>(fw.rng() & 0xFF);
    write(junk.data(), junk.size(), uart);
  }
  if (due(2, config_.faults.link_cut_at_s)) uart.cut();
}

void DeviceEmulator::sample_imus(std::uint32_t t, DeviceUart& uart) {
  Firmware& fw = *firmware_;
  const EmulatorEffects& fx = config_.effects;
  fw.next_data = t + kDataPeriodMs;
  const control::ImuReading sample = device_->plant.read_angles();
  fw.readings.push_back({t, sample.angles});
  while (fw.readings.size() > 1 && fw.readings[1].first + fw.latency_ms <= t) fw.readings.pop_front();
  const bool valid = !fw.imu_stale;
  if (valid) {
    fw.fe_cdeg = to_fixed(fw.readings.front().second.fe_deg + fx.imu_bias_fe_deg, 100.0);
    fw.ur_cdeg = to_fixed(fw.readings.front().second.ur_deg + fx.imu_bias_ur_deg, 100.0);
    fw.last_imu_ms = t;
  }
  fw.gate.imu_reading(valid, t);
  int32_t measured[4];
  for (int i = 0; i < 4; ++i) {
    measured[i] = to_fixed(device_->plant.wrist().regulated_pressure_kpa(static_cast<sim::MuscleIndex>(i)), 10.0);
  }
  send(fw.protocol.data_packet(t, fw.fe_cdeg, fw.ur_cdeg, measured), uart);
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.data_sent;
}

void DeviceEmulator::update_outputs(std::uint32_t t) {
  Firmware& fw = *firmware_;
  std::array<int32_t, 4> out{};
  fw.gate.update(t, out.data());
  const bool now_vented = std::all_of(out.begin(), out.end(), [](int32_t p) { return p == 0; });
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.max_output_dkpa = std::max(stats_.max_output_dkpa, *std::max_element(out.begin(), out.end()));
    if (now_vented && !fw.vented) {
      VentEvent e{.t_ms = t};
      if (fw.estop_pending) {
        e.cause = "emergency stop";
        e.cause_ms = fw.estop_ms;
      } else if (fw.hello_pending) {
        e.cause = "new session";
        e.cause_ms = fw.last_command_ms;
      } else if (fw.gate.flags(t) & wire::kWatchdog) {
        // Both timeouts may have run out by now; the cause is the one that ran out first.
        const bool no_command = fw.last_command_ms <= fw.last_imu_ms;
        e.cause = no_command ? "watchdog: no command" : "watchdog: no IMU";
        e.cause_ms = no_command ? fw.last_command_ms : fw.last_imu_ms;
      } else {
        e.cause = "zero command";
        e.cause_ms = fw.last_command_ms;
      }
      stats_.vents.push_back(e);
    }
    stats_.vented = now_vented;
  }
  fw.vented = now_vented;
  fw.estop_pending = fw.hello_pending = false;
  // The regulators see the setpoint after the dead time; venting is the valve, which needs no regulator.
  fw.setpoints.push_back({t, out});
  while (fw.setpoints.size() > 1 && fw.setpoints[1].first + fw.dead_time_ms <= t) fw.setpoints.pop_front();
  const std::array<int32_t, 4>& applied = now_vented ? out : fw.setpoints.front().second;
  // A regulator saturates at its range whatever the device's configured limit (the plant refuses anything else).
  const double max_kpa = device_->plant.max_pressure_kpa();
  const double dt_s = fw.last_output_ms ? (t - *fw.last_output_ms) / 1000.0 : 1e-3;
  fw.last_output_ms = t;
  const double alpha =
      config_.effects.pwm_steps ? pwm_filter_blend(dt_s, config_.effects.pwm_filter_time_constant_s) : 1.0;
  control::Pressures setpoints_kpa{};
  // Through the firmware's 8-bit PWM (pwm_scaling.h) and the board's RC filter: the regulators see its 0.54 kPa steps,
  // smoothed. Vented, the supply valve is closed whatever the filter still holds.
  for (std::size_t i = 0; i < 4; ++i) {
    const bool fast = wire::fast_pwm_muscle(static_cast<int>(i));
    const double kpa =
        config_.effects.pwm_steps ? wire::pwm_setpoint_kpa(wire::pwm_value(applied[i], fast), fast) : applied[i] / 10.0;
    fw.filtered_kpa[i] += alpha * (kpa - fw.filtered_kpa[i]);
    setpoints_kpa[i] = now_vented ? 0.0 : std::clamp(fw.filtered_kpa[i], 0.0, max_kpa);
  }
  device_->plant.command_pressures_kpa(setpoints_kpa);
}

void DeviceEmulator::tick(std::uint32_t t, DeviceUart& uart) {
  Firmware& fw = *firmware_;
  while (!fw.received.empty()) {
    const char c = fw.received.front();
    fw.received.pop_front();
    if (fw.lines.push(c)) handle_line(t, uart);
  }
  inject_faults(t, uart);
  device_->plant.wait_until(t / 1000.0);
  if (t >= fw.next_data) sample_imus(t, uart);
  update_outputs(t);
}

namespace {

// The emulator's pseudo-terminal as the firmware's UART: what does not fit is dropped; a host that went (it
// closed its side) may come back, as a new host opens the device node again.
class PseudoTerminalUart final : public DeviceUart {
 public:
  explicit PseudoTerminalUart(SerialPort link) : link_(std::move(link)) {}

  std::size_t write(const char* data, std::size_t size) override {
    if (!link_ || host_gone_) return 0;  // nobody listening: nothing counted as dropped
    try {
      return size - link_->write_some(data, size);
    } catch (const std::runtime_error&) {
      host_gone_ = true;
      return 0;
    }
  }
  void cut() override { link_.reset(); }  // the host's side reads EIO: unplugged

  // Waits up to `timeout_ms` for bytes from the host.
  std::size_t read(char* buffer, std::size_t size, int timeout_ms) {
    if (link_ && !host_gone_) {
      try {
        return link_->read_some(buffer, size, timeout_ms);
      } catch (const std::runtime_error&) {
        host_gone_ = true;  // the host closed its side; a new one may open it again
        return 0;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
    if (link_) {
      try {  // a pseudo-terminal whose host went reads again once a new host opens it
        const std::size_t n = link_->read_some(buffer, size, 0);
        host_gone_ = false;
        return n;
      } catch (const std::runtime_error&) {
      }
    }
    return 0;
  }

 private:
  std::optional<SerialPort> link_;
  bool host_gone_ = false;
};

}  // namespace

void DeviceEmulator::serve(SerialPort link, const std::atomic<bool>& stop) {
  try {
    serve_device(std::move(link), stop);
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.stopped_by = e.what();
    failed_ = true;
  }
}

void DeviceEmulator::serve_device(SerialPort link, const std::atomic<bool>& stop) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point epoch = Clock::now();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.epoch = epoch;
  }
  const auto now_ms = [&] {
    return static_cast<std::uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - epoch).count());
  };
  PseudoTerminalUart uart(std::move(link));
  std::uint32_t next_tick = 0;
  while (!stop.load()) {
    // Wait for bytes from the host until the next millisecond tick.
    const std::uint32_t before = now_ms();
    char buffer[256];
    receive(buffer, uart.read(buffer, sizeof buffer, next_tick > before ? static_cast<int>(next_tick - before) : 0));
    // One pass of the firmware's loop per millisecond (several when the emulator fell behind).
    const std::uint32_t now = now_ms();
    if (now > next_tick + 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_.max_loop_lag_ms = std::max(stats_.max_loop_lag_ms, now - next_tick);
    }
    for (; next_tick <= now; ++next_tick) tick(next_tick, uart);
  }
}

}  // namespace softwrist::bridge
