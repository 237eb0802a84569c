#include "bridge_apps/line_faults.h"

#include <stdexcept>

namespace softwrist::bridge {

const char* link_fault_name(LinkFault fault) {
  switch (fault) {
    case LinkFault::kLinkCut:
      return "link_cut";
    case LinkFault::kGarbageToHost:
      return "garbage_to_host";
    case LinkFault::kGarbageToDevice:
      return "garbage_to_device";
    case LinkFault::kStall:
      return "stall";
  }
  return "?";
}

LineFaults::LineFaults(LineFaultOptions options) : options_(options), rng_(options.seed) {
  if (!(options_.mean_interval_s > 0.0) || !(options_.min_duration_s > 0.0) ||
      !(options_.max_duration_s >= options_.min_duration_s)) {
    throw std::invalid_argument("line faults: the interval and durations must be positive, min <= max");
  }
  interval_ = std::exponential_distribution<double>(1.0 / options_.mean_interval_s);
  duration_ = std::uniform_real_distribution<double>(options_.min_duration_s, options_.max_duration_s);
  next_onset_s_ = options_.mean_interval_s;
}

LineFaults::Change LineFaults::advance(double now_s) {
  if (!active_ && now_s >= next_onset_s_) {
    active_ = InjectedFault{.kind = static_cast<LinkFault>(rng_() % 4),
                            .onset_s = now_s,
                            .duration_s = duration_(rng_),
                            .device_vented_at_onset = device_vented_};
    faults_.push_back(*active_);
    return Change::kOnset;
  }
  if (active_ && now_s >= active_->onset_s + active_->duration_s) {
    active_.reset();
    next_onset_s_ = now_s + interval_(rng_);
    return Change::kEnd;
  }
  return Change::kNone;
}

bool LineFaults::blocked() const {
  return active_ && (active_->kind == LinkFault::kStall || active_->kind == LinkFault::kLinkCut);
}

// Noise on the line: the bytes in transit replaced by random ones.
void LineFaults::garble(char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) data[i] = static_cast<char>(rng_() & 0xFF);
}

bool LineFaults::pass_to_host(char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    if (device_lines_.push(data[i]) &&
        watch_.handle_line(device_lines_.line(), device_lines_.length()) == DeviceLine::kData) {
      device_vented_ = (watch_.data().flags & wire::kVented) != 0;
    }
  }
  if (active_ && active_->kind == LinkFault::kGarbageToHost) garble(data, size);
  return !blocked();
}

bool LineFaults::pass_to_device(char* data, std::size_t size) {
  if (active_ && active_->kind == LinkFault::kGarbageToDevice) garble(data, size);
  return !blocked();
}

}  // namespace softwrist::bridge
