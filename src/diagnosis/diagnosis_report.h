#pragma once
// What `softwrist diagnose` writes: OUT/diagnosis.json (to_json), OUT/curves.csv (every measurement beside the
// nominal and corrected models' values), OUT/residual_map.csv (the localisation's angle x pressure cells) and
// OUT/diagnosis.html with plots (src/report/plot_diagnosis.py: real vs nominal vs corrected, the residual map).

#include <filesystem>
#include <string>
#include <vector>

#include "diagnosis/diagnosis.h"

namespace softwrist::diagnosis {

struct DiagnosisReportOptions {
  bool plots = true;
  double wall_s = 0.0;  // recorded in diagnosis.json
};

struct DiagnosisReport {
  std::filesystem::path json, page;
  std::vector<std::string> plots;
};

DiagnosisReport write_diagnosis_report(const Diagnosis& diagnosis, const std::filesystem::path& out,
                                       const DiagnosisReportOptions& options = {});

}  // namespace softwrist::diagnosis
