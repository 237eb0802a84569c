#include "cli/generate_command.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "independent_device/dataset.h"

namespace softwrist::cli {
namespace {

struct GenerateOptions {
  std::string out;
  std::uint64_t seed = 1;
  std::vector<std::string> effects;  // FORM or FORM:LEVEL
  double trajectory_s = 24.0;
  bool list = false;
};

// FORM or FORM:LEVEL.
independent::EffectSpec parse_effect(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) return {.form = text, .level = 1.0};
  return {.form = text.substr(0, colon),
          .level = parse_number(std::string_view(text).substr(colon + 1), "--effect '" + text + "' level")};
}

void run_generate(const GenerateOptions& o, std::ostream& out) {
  if (o.list) {
    for (const auto& f : independent::effect_forms()) {
      out << fmt::format("{:<26} {:<14} {}\n", f.name, f.label, f.description);
    }
    return;
  }
  if (o.out.empty()) throw UsageError("--out is required (or --list-forms)");
  independent::DatasetOptions options{.seed = o.seed, .effects = {}, .trajectory_s = o.trajectory_s};
  for (const auto& text : o.effects) options.effects.push_back(parse_effect(text));
  try {
    const independent::DatasetTruth truth = independent::write_dataset(options, o.out);
    std::string labels;
    for (const auto& l : truth.labels) labels += (labels.empty() ? "" : ",") + l;
    out << fmt::format("{}: {} files, manifest.json, truth.json (labels {}, largest effect {:.2f} noise units)\n",
                       o.out, truth.files.size(), labels, truth.magnitude_noise_units);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

}  // namespace

void add_generate_command(CLI::App& app, std::ostream& out) {
  auto o = std::make_shared<GenerateOptions>();
  auto* command = app.add_subcommand(
      "generate",
      "Data from the independent simulated exosuit (src/independent_device, written apart from softwrist's model): "
      "CSVs as real rigs give them, manifest.json (the conventions to state at import) and truth.json");
  command->add_option("--out", o->out, "Output directory");
  command->add_option("--seed", o->seed, "Seed of the device's variation, the conventions and the noise (default 1)");
  command->add_option("--effect", o->effects, "FORM or FORM:LEVEL (level in (0, 1], default 1); repeatable");
  command->add_option("--trajectory-s", o->trajectory_s,
                      "Length of each tracking trial (default 24 s; diagnose-bench's data sets are 12 s)");
  command->add_flag("--list-forms", o->list, "List the effect forms and the label a diagnosis should name");
  command->callback([o, &out] { run_generate(*o, out); });
}

}  // namespace softwrist::cli
