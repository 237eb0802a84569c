#include "hil/avr_board.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include <fcntl.h>
#include <gelf.h>
#include <libelf.h>
#include <unistd.h>

extern "C" {
#include <avr_adc.h>
#include <avr_extint.h>
#include <avr_ioport.h>
#include <avr_twi.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_io.h>
#include <sim_irq.h>
}

#include "bridge/wire_format.h"
#include "experiments/simulated_device.h"
#include "physics/units.h"
#include "sim/simulated_plant.h"

namespace softwrist::hil {
namespace {

constexpr std::uint64_t kCyclesPerMs = kAvrClockHz / 1000;

// ATmega328P data-space addresses (datasheet, Register Summary) of what the board's outputs are read from.
constexpr int kDdrB = 0x24, kPortB = 0x25, kDdrD = 0x2A, kPortD = 0x2B, kEimsk = 0x3D;
constexpr int kTccr0A = 0x44, kOcr0A = 0x47, kOcr0B = 0x48, kTccr1A = 0x80, kOcr1AL = 0x88, kTccr2A = 0xB0,
              kOcr2B = 0xB4;

// One PWM pin of the Uno: its port bit, and the timer output compare that drives it (Arduino's analogWrite: the COM
// bit connects the compare output; 0 and 255 are written as plain LOW and HIGH).
// Arduino runs timer 0 in fast PWM (duty (OCR + 1) / 256) and timers 1 and 2 in phase-correct PWM (duty OCR / 255).
struct PwmPin {
  int ddr, port, bit;
  int tccr, com_bit, ocr;
  bool fast;
};
// Pins 3 (PD3, OC2B), 5 (PD5, OC0B), 6 (PD6, OC0A), 9 (PB1, OC1A): flexor, extensor, ulnar, radial.
constexpr std::array<PwmPin, 4> kRegulatorPins = {{{kDdrD, kPortD, 3, kTccr2A, 5, kOcr2B, false},
                                                   {kDdrD, kPortD, 5, kTccr0A, 5, kOcr0B, true},
                                                   {kDdrD, kPortD, 6, kTccr0A, 7, kOcr0A, true},
                                                   {kDdrB, kPortB, 1, kTccr1A, 7, kOcr1AL, false}}};
constexpr int kValveBit = 7;         // PD7
constexpr int kSafetySwitchBit = 0;  // PB0
constexpr double kMonitorFullScaleMv = 5000.0;

// The two BNO055s on the bus (7-bit addresses 0x28, 0x29), as the firmware reads them.
struct Bno055Slave {
  std::uint8_t address = 0;  // 7-bit
  bool silent = false;
  bool stuck = false;                                      // acknowledges, then never sends the bytes it was asked for
  std::array<std::int16_t, 4> quaternion{16384, 0, 0, 0};  // w, x, y, z at 2^14 per unit
  std::uint8_t mode = 0;
  std::uint8_t reg = 0;
  int index = 0;  // bytes written in this transaction

  std::uint8_t read_register() {
    std::uint8_t value = 0;
    if (reg == 0x00) value = 0xA0;  // CHIP_ID
    if (reg == 0x3D) value = mode;
    // The fused quaternion reads zero outside a fusion mode (NDOF, 0x0C), as after the chip's own reset.
    if (reg >= 0x20 && reg <= 0x27 && mode == 0x0C) {
      const std::int16_t q = quaternion[static_cast<std::size_t>((reg - 0x20) / 2)];
      value = static_cast<std::uint8_t>(((reg - 0x20) % 2 == 0 ? q : q >> 8) & 0xFF);
    }
    ++reg;
    return value;
  }
};

// The hand's orientation relative to the forearm for the wrist angles the firmware's wrist_angles.h reads back:
// a rotation by fe about y after one by ur about z, so that the hand's x axis is (cos ur cos fe, sin ur,
// -cos ur sin fe).
std::array<std::int16_t, 4> hand_quaternion(double fe_rad, double ur_rad) {
  const double c1 = std::cos(fe_rad / 2), s1 = std::sin(fe_rad / 2), c2 = std::cos(ur_rad / 2),
               s2 = std::sin(ur_rad / 2);
  const std::array<double, 4> q = {c1 * c2, s1 * s2, s1 * c2, c1 * s2};
  std::array<std::int16_t, 4> out{};
  for (std::size_t i = 0; i < 4; ++i) out[i] = static_cast<std::int16_t>(std::lround(q[i] * 16384.0));
  return out;
}

// The addresses of the named symbols in an AVR ELF (data addresses without the ELF's 0x800000 data-space offset); 0
// where a name is missing.
// An ELF file opened with libelf for reading; get() is null when it is not one (or cannot be opened).
class ElfFile {
 public:
  explicit ElfFile(const std::filesystem::path& path) {
    elf_version(EV_CURRENT);
    fd_ = ::open(path.c_str(), O_RDONLY);
    if (fd_ >= 0) elf_ = elf_begin(fd_, ELF_C_READ, nullptr);
  }
  ~ElfFile() {
    if (elf_) elf_end(elf_);
    if (fd_ >= 0) ::close(fd_);
  }
  ElfFile(const ElfFile&) = delete;
  ElfFile& operator=(const ElfFile&) = delete;
  Elf* get() const { return elf_; }
  bool opened() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
  Elf* elf_ = nullptr;
};

std::array<std::uint32_t, 2> symbol_addresses(const std::filesystem::path& elf_path,
                                              const std::array<const char*, 2>& names) {
  std::array<std::uint32_t, 2> out{};
  const ElfFile file(elf_path);
  Elf* elf = file.get();
  for (Elf_Scn* scn = elf ? elf_nextscn(elf, nullptr) : nullptr; scn; scn = elf_nextscn(elf, scn)) {
    GElf_Shdr header;
    if (!gelf_getshdr(scn, &header) || header.sh_type != SHT_SYMTAB || header.sh_entsize == 0) continue;
    Elf_Data* data = elf_getdata(scn, nullptr);
    for (std::size_t i = 0; data && i < header.sh_size / header.sh_entsize; ++i) {
      GElf_Sym symbol;
      if (!gelf_getsym(data, static_cast<int>(i), &symbol)) continue;
      const char* name = elf_strptr(elf, header.sh_link, symbol.st_name);
      for (std::size_t k = 0; name && k < names.size(); ++k) {
        if (std::string_view(name) == names[k]) out[k] = static_cast<std::uint32_t>(symbol.st_value & 0xFFFF);
      }
    }
  }
  return out;
}

constexpr int kSpl = 0x5D, kSph = 0x5E;

// simavr's messages: errors only. Its default logger prints everything logged without an AVR (the ELF reader's
// "Loaded ... .text"); the logger is simavr's one global setting.
void errors_only(avr_t*, const int level, const char* format, va_list ap) {
  if (level <= LOG_ERROR) std::vfprintf(stderr, format, ap);
}

// What simavr's ELF reader allocated.
void free_firmware(elf_firmware_t& f) {
  std::free(f.flash);
  std::free(f.eeprom);
  std::free(f.fuse);
  std::free(f.lockbits);
  for (std::uint32_t i = 0; i < f.symbolcount; ++i) std::free(f.symbol[i]);
  std::free(f.symbol);
  f = elf_firmware_t{};
}

// An ELF for the AVR (simavr's reader accepts other files without complaint).
bool is_avr_elf(const std::filesystem::path& path) {
  const ElfFile file(path);
  GElf_Ehdr header;
  return file.get() && elf_kind(file.get()) == ELF_K_ELF && gelf_getehdr(file.get(), &header) &&
         header.e_machine == EM_AVR;
}

}  // namespace

struct AvrBoard::Impl {
  Impl(const std::filesystem::path& firmware, const bridge::EmulatorConfig& config)
      : pwm_filter_time_constant_s(config.effects.pwm_filter_time_constant_s),
        simulated(bridge::emulated_description(config), sim::ModelOptions{.gravity = config.gravity}),
        plant(simulated.model, units::pa_to_kpa(simulated.description.regulator.max_pressure),
              sim::ImuModel{.period_s = 0.01,
                            .noise_std_deg = config.effects.imu_noise_std_deg,
                            .bias_limit_deg = 0.0,
                            .seed = config.seed}) {
    load(firmware);
    imus[0].address = 0x28;
    imus[1].address = 0x29;
  }
  ~Impl() {
    if (avr) {
      if (twi) avr_free_irq(twi, 2);
      avr_terminate(avr);  // frees its flash and data, not itself
      std::free(avr);
    }
  }

  void load(const std::filesystem::path& firmware) {
    avr_global_logger_set(&errors_only);
    elf_firmware_t f{};
    if (!is_avr_elf(firmware) || elf_read_firmware(firmware.c_str(), &f) != 0) {
      free_firmware(f);
      throw std::runtime_error(fmt::format(
          "{}: cannot read as AVR firmware (an ELF built by scripts/build_firmware.sh)", firmware.string()));
    }
    avr = avr_make_mcu_by_name("atmega328p");
    if (!avr) throw std::runtime_error("simavr has no ATmega328P");
    avr_init(avr);
    avr->log = LOG_ERROR;
    avr->sleep = [](avr_t*, avr_cycle_count_t) {};  // simulated time: never wait on the host's clock
    avr_load_firmware(avr, &f);                     // copies the program into the AVR's flash
    free_firmware(f);
    const auto symbols = symbol_addresses(firmware, {"loop", "__heap_start"});
    loop_address = symbols[0];
    heap_start = symbols[1];
    avr->frequency = kAvrClockHz;
    avr->vcc = avr->avcc = avr->aref = 5000;
    wire_uart();
    wire_twi();
    set_safety_switch(false);
    external_interrupts_on_edges();
  }

  // simavr polls INT0 and INT1 (PD2, PD3) on every cycle while their pin is low, for their default low-level mode,
  // whether or not the interrupt is enabled: pin 3 is a PWM output, low most of each period, and the poll took a
  // sixth of the run's time (perf). The firmware enables neither (read_outputs() refuses one that does), so the
  // poll can never raise anything. simavr turns it back on at every reset.
  void external_interrupts_on_edges() {
    avr_extint_set_strict_lvl_trig(avr, 0, 0);
    avr_extint_set_strict_lvl_trig(avr, 1, 0);
  }

  void wire_uart() {
    std::uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~static_cast<std::uint32_t>(AVR_UART_FLAG_STDIO);
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_register_notify(
        avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
        [](avr_irq_t*, std::uint32_t value, void* self) {
          static_cast<Impl*>(self)->from_avr.push_back(static_cast<char>(value & 0xFF));
        },
        this);
    avr_irq_register_notify(
        avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF),
        [](avr_irq_t*, std::uint32_t, void* self) { static_cast<Impl*>(self)->uart_ready = false; }, this);
    avr_irq_register_notify(
        avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON),
        [](avr_irq_t*, std::uint32_t, void* self) { static_cast<Impl*>(self)->uart_ready = true; }, this);
    uart_input = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  }

  void wire_twi() {
    static const char* names[2] = {"twi.slave.in", "twi.slave.out"};
    twi = avr_alloc_irq(&avr->irq_pool, 0, 2, names);
    avr_connect_irq(twi + TWI_IRQ_INPUT, avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT));
    avr_connect_irq(avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), twi + TWI_IRQ_OUTPUT);
    avr_irq_register_notify(
        twi + TWI_IRQ_OUTPUT,
        [](avr_irq_t*, std::uint32_t value, void* self) { static_cast<Impl*>(self)->on_twi(value); }, this);
  }

  // The bus as the slaves see it (simavr's messages; addresses are 8-bit, the 7-bit one shifted with R/W in bit 0).
  void on_twi(std::uint32_t value) {
    avr_twi_msg_irq_t m;
    m.u.v = value;
    const std::uint8_t msg = m.u.twi.msg;
    if (msg & TWI_COND_STOP) {
      if (transaction_read_quaternion) {
        const std::uint64_t cycles = avr->cycle - transaction_start;
        stats.i2c_read_max_cycles = std::max(stats.i2c_read_max_cycles, cycles);
        stats.i2c_read_cycles_total += cycles;
        ++stats.i2c_read_transactions;
      }
      transaction_read_quaternion = false;
      selected = nullptr;
    }
    if (msg & TWI_COND_START) {
      transaction_start = avr->cycle;
      transaction_read_quaternion = false;
      selected = nullptr;
      for (Bno055Slave& s : imus) {
        if (!s.silent && (m.u.twi.addr >> 1) == s.address) selected = &s;
      }
      if (selected) {
        selected->index = 0;
        avr_raise_irq(twi + TWI_IRQ_INPUT, avr_twi_irq_msg(TWI_COND_ACK, m.u.twi.addr, 1));
      }
    }
    if (!selected) return;
    if (msg & TWI_COND_WRITE) {
      avr_raise_irq(twi + TWI_IRQ_INPUT, avr_twi_irq_msg(TWI_COND_ACK, m.u.twi.addr, 1));
      if (selected->index == 0) {
        selected->reg = m.u.twi.data;
      } else if (selected->reg == 0x3D) {
        selected->mode = m.u.twi.data;
      }
      ++selected->index;
    }
    if ((msg & TWI_COND_READ) && selected->stuck) return;
    if (msg & TWI_COND_READ) {
      if (selected->reg == 0x20) {
        ++stats.i2c_reads;
        transaction_read_quaternion = true;
      }
      avr_raise_irq(twi + TWI_IRQ_INPUT, avr_twi_irq_msg(TWI_COND_READ, m.u.twi.addr, selected->read_register()));
    }
  }

  void set_safety_switch(bool open) {
    switch_open = open;
    // Closed to ground: the pin reads low; open, the firmware's pull-up makes it high. Set as the pin's external
    // level, so it holds whatever the firmware writes to the port (its pull-up, a reset).
    avr_ioport_external_t level{};
    level.name = 'B';
    level.mask = 1U << kSafetySwitchBit;
    level.value = open ? 1U << kSafetySwitchBit : 0U;
    avr_ioctl(avr, AVR_IOCTL_IOPORT_SET_EXTERNAL('B'), &level);
    avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('B'), kSafetySwitchBit), open ? 1 : 0);
  }

  // Runs the AVR to the end of millisecond `t_ms`, feeding it the host's bytes as its UART takes them.
  void run_to(std::uint32_t t_ms) {
    const std::uint64_t end = (static_cast<std::uint64_t>(t_ms) + 1) * kCyclesPerMs;
    while (avr->cycle < end) {
      while (!to_avr.empty() && uart_ready) {
        avr_raise_irq(uart_input, static_cast<std::uint8_t>(to_avr.front()));
        to_avr.pop_front();
        ++stats.bytes_to_avr;
      }
      const std::uint32_t pc_before = avr->pc;
      const int state = avr_run(avr);
      // simavr 1.6's avr_reset keeps avr->cycle counting (newer simavr zeroes it, which would break this clock).
      if (avr->pc == 0 && pc_before != 0) {
        ++stats.resets;
        stats.reset_ms.push_back(static_cast<std::uint32_t>(avr->cycle / kCyclesPerMs));
        last_loop_cycle = 0;
        release_hang();
        external_interrupts_on_edges();
      }
      measure();
      if (state == cpu_Done || state == cpu_Crashed) {
        throw std::runtime_error(fmt::format("the simulated ATmega328P stopped at {} ms (state {})", t_ms, state));
      }
    }
    stats.cycles = avr->cycle;
    if (heap_start != 0) stats.stack_headroom_bytes = min_sp + 1 - static_cast<int>(heap_start);
  }

  // `rjmp .-2` (0xCFFF: a relative jump by -1 word, to itself) over loop()'s first instruction; the original back at a
  // reset. simavr decodes every instruction from flash as it runs it, so the patch acts at once.
  void hang() {
    if (loop_address == 0) throw std::runtime_error("the firmware has no loop() symbol to hang");
    if (hung) return;
    hung = true;
    saved_loop_word = {avr->flash[loop_address], avr->flash[loop_address + 1]};
    avr->flash[loop_address] = 0xFF;
    avr->flash[loop_address + 1] = 0xCF;
  }
  void release_hang() {
    if (!hung) return;
    hung = false;
    avr->flash[loop_address] = saved_loop_word[0];
    avr->flash[loop_address + 1] = saved_loop_word[1];
  }

  // Loop passes and the stack, after every instruction.
  void measure() {
    if (loop_address != 0 && avr->pc == loop_address && !hung) {
      if (last_loop_cycle != 0) {
        const std::uint64_t pass = avr->cycle - last_loop_cycle;
        stats.loop_max_cycles = std::max(stats.loop_max_cycles, pass);
        stats.loop_cycles_total += pass;
        ++stats.loops;
      }
      last_loop_cycle = avr->cycle;
    }
    const int sp = avr->data[kSpl] | (avr->data[kSph] << 8);
    if (heap_start != 0 && sp > 0x100) min_sp = std::min(min_sp, sp);
  }

  // The regulators' setpoints from the PWM pins (through the RC filter) and the valve.
  void read_outputs(double dt_s) {
    const auto bit = [this](int address, int b) { return (avr->data[address] >> b) & 1; };
    if (avr->data[kEimsk] & 0x03) {
      throw std::runtime_error("the firmware enabled INT0 or INT1, which the simulated board does not model");
    }
    const bool valve_open = bit(kDdrD, kValveBit) && bit(kPortD, kValveBit);
    const double max_kpa = plant.max_pressure_kpa();
    const double alpha = bridge::pwm_filter_blend(dt_s, pwm_filter_time_constant_s);
    for (std::size_t i = 0; i < 4; ++i) {
      const PwmPin& p = kRegulatorPins[i];
      double duty = 0.0;
      if (bit(p.ddr, p.bit)) {
        const double ocr = avr->data[p.ocr];
        duty = !bit(p.tccr, p.com_bit) ? bit(p.port, p.bit) : p.fast ? (ocr + 1.0) / 256.0 : ocr / 255.0;
      }
      filtered[i] += alpha * (duty * max_kpa - filtered[i]);
      setpoints[i] = valve_open ? std::clamp(filtered[i], 0.0, max_kpa) : 0.0;
    }
  }

  void update_inputs() {
    for (int i = 0; i < 4; ++i) {
      const double kpa = plant.wrist().regulated_pressure_kpa(static_cast<sim::MuscleIndex>(i));
      const double mv = std::clamp(kpa / plant.max_pressure_kpa(), 0.0, 1.0) * kMonitorFullScaleMv;
      avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + i),
                    static_cast<std::uint32_t>(std::lround(mv)));
    }
    const control::ImuReading r = plant.read_angles();
    imus[1].quaternion = hand_quaternion(units::deg_to_rad(r.angles.fe_deg), units::deg_to_rad(r.angles.ur_deg));
  }

  // The emulated subject, as the emulator's: at each hello the wrist is put at neutral and held there, vented,
  // until the first command.
  void watch_host(const char* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      if (!host_lines.push(data[i])) continue;
      wire::Packet p{};
      if (wire::parse_line(host_lines.line(), host_lines.length(), &p) != wire::kOk) continue;
      if (p.type == wire::kHelloPacket) plant.hold(control::WristAngles{});
      if (p.type == wire::kSetPacket) plant.hold(std::nullopt);
    }
  }

  double pwm_filter_time_constant_s;
  std::uint32_t loop_address = 0, heap_start = 0;
  std::uint64_t last_loop_cycle = 0, transaction_start = 0;
  bool transaction_read_quaternion = false;
  bool hung = false;
  std::array<std::uint8_t, 2> saved_loop_word{};
  int min_sp = 0x8FF;  // RAMEND
  experiments::SimulatedDevice simulated;
  sim::SimulatedPlant plant;
  avr_t* avr = nullptr;
  avr_irq_t* uart_input = nullptr;
  avr_irq_t* twi = nullptr;
  bool uart_ready = true;
  bool switch_open = false;
  std::deque<char> to_avr;
  std::vector<char> from_avr;
  std::array<Bno055Slave, 2> imus;
  Bno055Slave* selected = nullptr;
  std::array<double, 4> filtered{};
  control::Pressures setpoints{};
  wire::LineAssembler host_lines;
  BoardStats stats;
};

AvrBoard::AvrBoard(const std::filesystem::path& firmware, const bridge::EmulatorConfig& plant)
    : impl_(std::make_unique<Impl>(firmware, plant)) {}

AvrBoard::~AvrBoard() = default;

void AvrBoard::receive(const char* data, std::size_t size) {
  impl_->watch_host(data, size);
  impl_->to_avr.insert(impl_->to_avr.end(), data, data + size);
}

void AvrBoard::tick(std::uint32_t t_ms, bridge::DeviceUart& uart) {
  Impl& b = *impl_;
  b.update_inputs();
  b.run_to(t_ms);
  if (!b.from_avr.empty()) {
    b.stats.bytes_from_avr += static_cast<long>(b.from_avr.size());
    uart.write(b.from_avr.data(), b.from_avr.size());
    b.from_avr.clear();
  }
  b.read_outputs(1e-3);
  const bool vented = std::all_of(b.setpoints.begin(), b.setpoints.end(), [](double p) { return p < 0.05; });
  if (vented && !b.stats.vented) b.stats.vent_ms.push_back(t_ms);
  b.stats.vented = vented;
  for (double p : b.setpoints) b.stats.max_setpoint_kpa = std::max(b.stats.max_setpoint_kpa, p);
  b.plant.command_pressures_kpa(b.setpoints);
  b.plant.wait_until((t_ms + 1) / 1000.0);
}

void AvrBoard::set_safety_switch_open(bool open) { impl_->set_safety_switch(open); }

void AvrBoard::set_imu_silent(int imu, bool silent) { impl_->imus.at(static_cast<std::size_t>(imu)).silent = silent; }

void AvrBoard::set_imu_stuck(int imu, bool stuck) { impl_->imus.at(static_cast<std::size_t>(imu)).stuck = stuck; }

void AvrBoard::reset_imu(int imu) { impl_->imus.at(static_cast<std::size_t>(imu)).mode = 0; }

void AvrBoard::hang_firmware() { impl_->hang(); }

const BoardStats& AvrBoard::stats() const { return impl_->stats; }

control::Pressures AvrBoard::setpoints_kpa() const { return impl_->setpoints; }

control::WristAngles AvrBoard::true_angles() const { return impl_->plant.true_angles(); }

control::Pressures AvrBoard::regulated_pressures_kpa() const {
  control::Pressures p{};
  for (std::size_t i = 0; i < 4; ++i) {
    p[i] = impl_->plant.wrist().regulated_pressure_kpa(static_cast<sim::MuscleIndex>(i));
  }
  return p;
}

FirmwareSize firmware_size(const std::filesystem::path& firmware) {
  const ElfFile file(firmware);
  if (!file.opened()) throw std::runtime_error(firmware.string() + ": cannot open");
  Elf* elf = file.get();
  std::size_t names = 0;
  if (!elf || elf_getshdrstrndx(elf, &names) != 0) throw std::runtime_error(firmware.string() + ": not an ELF file");
  FirmwareSize size;
  for (Elf_Scn* scn = elf_nextscn(elf, nullptr); scn; scn = elf_nextscn(elf, scn)) {
    GElf_Shdr header;
    const char* name = gelf_getshdr(scn, &header) ? elf_strptr(elf, names, header.sh_name) : nullptr;
    if (!name) continue;
    const std::string_view section = name;
    const long bytes = static_cast<long>(header.sh_size);
    if (section == ".text" || section == ".data") size.flash_bytes += bytes;
    if (section == ".data" || section == ".bss") size.ram_bytes += bytes;
  }
  return size;
}

}  // namespace softwrist::hil
