#include "experiments/trial_log.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <fmt/format.h>

#include "io/json_reader.h"
#include "io/text_file.h"

#ifndef SOFTWRIST_VERSION
#error "SOFTWRIST_VERSION must be defined by the build"
#endif

namespace softwrist::experiments {

nlohmann::json to_json(const LogHeader& header) {
  nlohmann::json columns = nlohmann::json::array();
  for (const auto& c : header.columns) {
    columns.push_back({{"name", c.name}, {"unit", c.unit}, {"description", c.description}});
  }
  return {{"format", kLogFormat},
          {"kind", header.kind},
          {"source", header.source},
          {"software_version", SOFTWRIST_VERSION},
          {"config", header.config},
          {"config_dir", header.config_dir},
          {"config_hash", header.config_hash},
          {"model_hash", header.model_hash},
          {"columns", columns},
          {"cases",
           {{"total", header.case_count}, {"shard", fmt::format("{}/{}", header.shard_index, header.shard_count)}}}};
}

LogHeader log_header_from_json(const nlohmann::json& sidecar, const std::string& source) {
  io::JsonReader top(sidecar, source, "");
  if (const std::string format = top.text("format"); format != kLogFormat) {
    top.fail("format", fmt::format("'{}' is not '{}'", format, kLogFormat));
  }
  LogHeader header;
  header.kind = top.text("kind");
  header.source = top.text("source", "simulation");
  (void)top.text("software_version", "");
  header.config = top.raw("config");
  header.config_dir = top.text("config_dir", "");
  header.config_hash = top.text("config_hash", "");
  header.model_hash = top.text("model_hash", "");
  const nlohmann::json& columns = top.raw("columns");
  if (!columns.is_array() || columns.empty()) top.fail("columns", "must be a non-empty list");
  for (std::size_t i = 0; i < columns.size(); ++i) {
    io::JsonReader c(columns[i], source, fmt::format("columns[{}]", i));
    header.columns.push_back({c.text("name"), c.text("unit", ""), c.text("description", "")});
    c.finish();
  }
  io::JsonReader cases = top.child("cases");
  header.case_count = static_cast<int>(cases.integer("total"));
  const std::string shard = cases.text("shard", "1/1");
  if (std::sscanf(shard.c_str(), "%d/%d", &header.shard_index, &header.shard_count) != 2 || header.shard_index < 1 ||
      header.shard_index > header.shard_count) {
    cases.fail("shard", fmt::format("'{}' is not K/N with 1 <= K <= N", shard));
  }
  cases.finish();
  top.finish();
  return header;
}

namespace {

std::vector<std::string> column_names(const LogHeader& header) {
  std::vector<std::string> names;
  for (const auto& c : header.columns) names.push_back(c.name);
  return names;
}

std::filesystem::path csv_path_in_new_dir(const std::filesystem::path& dir, const std::string& name) {
  std::filesystem::create_directories(dir);
  return dir / (name + ".csv");
}

void write_sidecar(const std::filesystem::path& dir, const std::string& name, const LogHeader& header) {
  const auto sidecar_path = dir / (name + ".json");
  std::ofstream sidecar(sidecar_path);
  sidecar << to_json(header).dump(2) << '\n';
  if (!sidecar) throw std::runtime_error(sidecar_path.string() + ": cannot write");
}

// The kept rows go to a scratch file renamed over the log, so that a kill during the rewrite loses nothing.
std::filesystem::path rewrite_kept_rows(const std::filesystem::path& dir, const std::string& name,
                                        const LogHeader& header,
                                        const std::vector<std::vector<std::string>>& kept_rows) {
  const auto path = csv_path_in_new_dir(dir, name);
  const auto scratch = dir / (name + ".csv.resuming");
  {
    io::CsvWriter kept(scratch, column_names(header));
    for (const auto& row : kept_rows) kept.write_row(row);
  }
  std::filesystem::rename(scratch, path);
  return path;
}

}  // namespace

LogWriter::LogWriter(const std::filesystem::path& dir, const std::string& name, const LogHeader& header)
    : csv_(csv_path_in_new_dir(dir, name), column_names(header)) {
  write_sidecar(dir, name, header);
}

LogWriter::LogWriter(const std::filesystem::path& dir, const std::string& name, const LogHeader& header,
                     const std::vector<std::vector<std::string>>& kept_rows)
    : csv_(rewrite_kept_rows(dir, name, header, kept_rows), column_names(header), io::CsvWriter::Append{}) {
  write_sidecar(dir, name, header);
}

TrialLog read_log(const std::filesystem::path& dir, const std::string& name) {
  const auto sidecar_path = dir / (name + ".json");
  const std::string source = sidecar_path.string();
  LogHeader header = log_header_from_json(io::parse_json(io::read_text_file(sidecar_path), source), source);
  const auto csv_path = dir / (name + ".csv");
  std::string text = io::read_text_file(csv_path);
  int unfinished_line = 0;
  if (!text.empty() && text.back() != '\n') {
    unfinished_line = 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
    const auto last_newline = text.rfind('\n');
    text.erase(last_newline == std::string::npos ? 0 : last_newline + 1);
  }
  TrialLog log{.header = std::move(header),
               .table = io::CsvTable::Parse(text, csv_path.string()),
               .unfinished_line = unfinished_line};
  if (log.table.header() != column_names(log.header)) {
    throw std::runtime_error((dir / (name + ".csv")).string() + ": columns differ from the sidecar's " + source);
  }
  return log;
}

std::string content_hash(std::string_view text) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return fmt::format("fnv1a64:{:016x}", hash);
}

}  // namespace softwrist::experiments
