#pragma once
// `softwrist personalize --user user.json`: the four fPAMs' placement for one user (Fig.
// Personalization_pipeline), written as a placement file and the generated MuJoCo model.
#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_personalize_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
