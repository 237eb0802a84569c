#include "experiments/experiment.h"

#include "experiments/design_optimization.h"
#include "experiments/range_of_motion.h"
#include "experiments/torque_validation.h"
#include "experiments/tracking.h"
#include "io/text_file.h"

namespace softwrist::experiments {

ExperimentConfig load_experiment_config(const std::filesystem::path& path) {
  return {.json = io::parse_json(io::read_text_file(path), path.string()),
          .base_dir = std::filesystem::absolute(path).parent_path(),
          .source = path.string(),
          .name = path.stem().string()};
}

std::unique_ptr<Experiment> make_experiment(const ExperimentConfig& config) {
  io::JsonReader reader(config.json, config.source, "");
  if (const std::string format = reader.text("format"); format != kConfigFormat) {
    reader.fail("format", fmt::format("'{}' is not '{}'", format, kConfigFormat));
  }
  (void)reader.text("description", "");
  const std::string kind = reader.text("kind");
  std::unique_ptr<Experiment> experiment;
  if (kind == "torque_validation") {
    experiment = TorqueValidation::Create(config, reader);
  } else if (kind == "range_of_motion") {
    experiment = RangeOfMotion::Create(config, reader);
  } else if (kind == "design_optimization") {
    experiment = DesignOptimization::Create(config, reader);
  } else if (kind == "tracking") {
    experiment = Tracking::Create(config, reader);
  } else {
    reader.fail("kind",
                fmt::format("'{}' is not torque_validation, range_of_motion, design_optimization or tracking", kind));
  }
  reader.finish();
  return experiment;
}

std::mt19937_64 case_rng(std::uint64_t seed, int case_index) {
  std::seed_seq sequence{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                         static_cast<std::uint32_t>(case_index)};
  return std::mt19937_64(sequence);
}

Repetitions read_repetitions(io::JsonReader& reader) {
  Repetitions r{.count = static_cast<int>(reader.integer("repetitions", 3)),
                .seed = static_cast<std::uint64_t>(reader.integer("seed", 1))};
  if (r.count < 1 || r.count > 1000) reader.fail("repetitions", "must be 1..1000");
  return r;
}

std::filesystem::path config_path(io::JsonReader& reader, const std::string& key, const ExperimentConfig& config) {
  const std::filesystem::path path = reader.text(key);
  if (path.empty()) reader.fail(key, "must name a file");
  const std::filesystem::path resolved = path.is_absolute() ? path : config.base_dir / path;
  if (!std::filesystem::is_regular_file(resolved)) reader.fail(key, "no such file: " + resolved.string());
  return resolved;
}

}  // namespace softwrist::experiments
