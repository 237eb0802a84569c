// Fuzz target: experiment configs (docs/experiments.md), as `softwrist run` reads them: the JSON, then the
// experiment it describes, with relative paths starting at experiments/ of the source tree (so the seed corpus's
// configs find their reference files). A config is either rejected with an error naming the file (and the field),
// or becomes an experiment with cases; nothing is run.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "experiments/experiment.h"
#include "fuzz_check.h"
#include "io/json_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softwrist;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const experiments::ExperimentConfig config{.json = io::parse_json(text, "fuzz.json"),
                                               .base_dir = SOFTWRIST_SOURCE_DIR "/experiments",
                                               .source = "fuzz.json",
                                               .name = "fuzz"};
    const auto experiment = experiments::make_experiment(config);
    FUZZ_CHECK(experiment->case_count() > 0);
    FUZZ_CHECK(!experiment->columns().empty());
  } catch (const std::runtime_error& e) {
    fuzz::check_names_source(e.what(), "fuzz.json");
  }
  return 0;
}
