#pragma once
// The look every softwrist page shares (the run report and the diagnosis): one small stylesheet written beside the
// page as style.css (no JavaScript framework, nothing fetched: the page works offline from its directory), the result
// first in a summary box, the paper's figures highlighted where they stand beside the simulated ones, and a check the
// page runs on load that the headless-browser test reads back.

#include <filesystem>
#include <string>
#include <vector>

namespace softwrist::report {

// Writes DIR/style.css.
void write_stylesheet(const std::filesystem::path& dir);

// <!DOCTYPE html> to the page's <h1> and the line under it (escaped here).
std::string page_head(const std::string& title, const std::string& subtitle);

// The result first: each line is HTML (escape what came from a file). `attention`: a box that says something is wrong
// or left over (a red edge instead of a blue one).
std::string summary_box(const std::vector<std::string>& lines, bool attention = false);

// The closing script and tags. On load the page replaces an image that did not load with a note naming it, and
// writes on <body> the count of loaded images (data-images="loaded/all") and the boxes whose text overflows them
// (data-overflow="none", or each such box's tag, class and first words).
std::string page_end();

}  // namespace softwrist::report
