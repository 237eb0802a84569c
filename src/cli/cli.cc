#include "cli/cli.h"

#include <exception>

#include <CLI/CLI.hpp>

#include "cli/arguments.h"
#include "cli/bench_commands.h"
#include "cli/bridge_commands.h"
#include "cli/calibrate_command.h"
#include "cli/diagnose_commands.h"
#include "cli/generate_command.h"
#include "cli/model_commands.h"
#include "cli/personalize_command.h"
#include "cli/render_command.h"
#include "cli/report_command.h"
#include "cli/run_commands.h"
#include "cli/view_command.h"
#include "physics/errors.h"

namespace softwrist::cli {

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "softwrist: simulation testbed for a soft wrist exosuit driven by fabric pneumatic artificial "
      "muscles (fPAMs)",
      "softwrist"};
  app.option_defaults()->always_capture_default();
  app.require_subcommand(1);
  app.set_version_flag("--version", SOFTWRIST_VERSION);
  add_model_commands(app, out);
  add_bench_commands(app, out, err);
  add_render_command(app, out);
  add_report_command(app, out);
  add_run_commands(app, out, err);
  add_personalize_command(app, out);
  add_view_command(app, out);
  add_bridge_commands(app, out, err);
  add_calibrate_command(app, out, err);
  add_diagnose_commands(app, out, err);
  add_generate_command(app, out);

  std::vector<const char*> argv = {"softwrist"};
  for (const auto& arg : args) argv.push_back(arg.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    // --help is a ParseError of code 0; every other (a missing, unknown or conflicting option) is a bad argument,
    // exit code 2 as the README says, whatever CLI11's own number for it.
    return app.exit(e, out, err) == 0 ? 0 : 2;
  } catch (const UsageError& e) {
    err << "error: " << e.what() << '\n';
    return 2;
  } catch (const physics::InvalidParameter& e) {
    err << "error: invalid parameter: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    err << "error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}

}  // namespace softwrist::cli
