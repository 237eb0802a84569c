#include "report/page_style.h"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "report/html_report.h"

namespace softwrist::report {
namespace {

// Readable type (a system sans at 16 px, 1.5 line height), tables with tabular figures, and the paper's column
// tinted: what a reader compares sits side by side.
constexpr const char* kStylesheet = R"(/* softwrist report pages (src/report/page_style.cc) */
:root { --ink: #1f252d; --muted: #5a6471; --line: #d9dee4; --accent: #2b6f97; --attention: #b3261e;
        --paper: #fbf3dc; --paper-head: #f1dfa6; }
* { box-sizing: border-box; }
body { font: 16px/1.5 "DejaVu Sans", "Liberation Sans", Arial, sans-serif; color: var(--ink); background: #fcfcfb;
       max-width: 1120px; margin: 0 auto; padding: 1.5rem 2rem 3rem; }
h1 { font-size: 1.75rem; line-height: 1.25; margin: 0.5rem 0 0.2rem; overflow-wrap: anywhere; }
h2 { font-size: 1.3rem; margin: 2.2rem 0 0.6rem; padding-bottom: 0.2rem; border-bottom: 1px solid var(--line); }
h3 { font-size: 1.05rem; margin: 1.4rem 0 0.4rem; }
.subtitle { color: var(--muted); margin: 0 0 1rem; }
.summary { border-left: 5px solid var(--accent); background: #edf4f8; padding: 0.7rem 1.2rem; margin: 1.2rem 0 1.6rem;
           border-radius: 4px; }
.summary.attention { border-left-color: var(--attention); background: #fbefed; }
.summary p { margin: 0.35rem 0; }
.table-wrap { max-width: 100%; overflow-x: auto; }
table { border-collapse: collapse; margin: 0.8rem 0 1.2rem; font-size: 0.92rem; }
th, td { border-bottom: 1px solid var(--line); padding: 0.35rem 0.75rem; text-align: left; vertical-align: top;
         overflow-wrap: break-word; }
th { background: #eef1f4; font-weight: 600; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
td.num { white-space: nowrap; }
th.paper { background: var(--paper-head); }
td.paper { background: var(--paper); }
tr.significant td:first-child { border-left: 4px solid var(--attention); }
tr.located td:first-child { border-left: 4px solid #d99a1e; }
.note { color: var(--muted); font-size: 0.9rem; }
figure { margin: 1.4rem 0; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line); background: #fff; }
figcaption { color: var(--muted); font-size: 0.9rem; margin-top: 0.3rem; }
.renders { display: grid; grid-template-columns: repeat(auto-fit, minmax(300px, 1fr)); gap: 0 1.5rem; }
pre { background: #f2f3f4; padding: 1rem; overflow-x: auto; font-size: 0.82rem; }
details { margin: 0.8rem 0; }
.missing { color: var(--attention); font-weight: bold; }
)";

constexpr const char* kPageEnd = R"(<script>
window.addEventListener("load", () => {
  const images = Array.from(document.images);
  const missing = images.filter((img) => !img.complete || img.naturalWidth === 0);
  for (const img of missing) {
    const note = document.createElement("p");
    note.className = "missing";
    note.textContent = "image missing: " + img.getAttribute("src");
    img.replaceWith(note);
  }
  document.body.dataset.images = (images.length - missing.length) + "/" + images.length;
  // A box overflows when its content is wider than it and it does not scroll, or when it reaches past the window.
  const width = document.documentElement.clientWidth;
  const overflowing = [];
  for (const el of document.body.querySelectorAll("*")) {
    const style = getComputedStyle(el);
    if (style.display === "inline" || style.display === "none" || el.closest("script")) continue;
    const scrolls = style.overflowX === "auto" || style.overflowX === "scroll" || el.closest("pre, .table-wrap");
    const right = el.getBoundingClientRect().right;
    if ((!scrolls && el.scrollWidth > el.clientWidth + 1) || (!el.closest(".table-wrap, pre") && right > width + 1)) {
      overflowing.push(el.tagName.toLowerCase() + (el.className ? "." + el.className : "") + " '" +
                       el.textContent.trim().slice(0, 40) + "'");
    }
  }
  document.body.dataset.overflow = overflowing.length ? overflowing.join("; ") : "none";
});
</script>
</body></html>
)";

}  // namespace

void write_stylesheet(const std::filesystem::path& dir) {
  std::ofstream file(dir / "style.css");
  file << kStylesheet;
  if (!file) throw std::runtime_error((dir / "style.css").string() + ": could not be written");
}

std::string page_head(const std::string& title, const std::string& subtitle) {
  return fmt::format(R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>{0}</title>
<link rel="stylesheet" href="style.css">
</head><body>
<h1>{0}</h1>
{1}
)",
                     html_escape(title),
                     subtitle.empty() ? "" : fmt::format("<p class=\"subtitle\">{}</p>", html_escape(subtitle)));
}

std::string summary_box(const std::vector<std::string>& lines, bool attention) {
  std::string html = fmt::format("<section class=\"summary{}\">\n", attention ? " attention" : "");
  for (const std::string& line : lines) html += "<p>" + line + "</p>\n";
  return html + "</section>\n";
}

std::string page_end() { return kPageEnd; }

}  // namespace softwrist::report
