#include "diagnosis/joint_refit.h"

#include "optimize/bounded_least_squares.h"

namespace softwrist::diagnosis {

ModelVariant combined_variant(const std::vector<EffectFit>& combination, const std::vector<std::vector<double>>& values,
                              const ModelVariant& nominal) {
  // With the nominal's rigs: a trial that names its placement is replayed on that rig (ModelVariant::device_for), and
  // without it every replay of a two-rig data set failed and the refit had no start.
  ModelVariant v = nominal;
  for (std::size_t e = 0; e < combination.size(); ++e) apply_effect(combination[e].id, values[e], v);
  return v;
}

ModelVariant refit_jointly(const GapProblem& problem, std::vector<EffectFit>& combination, const ModelVariant& nominal,
                           const DiagnosisOptions& options) {
  std::vector<std::vector<double>> values;
  std::vector<double> start;
  for (const EffectFit& f : combination) {
    values.push_back(f.values);
    const EffectSpec& spec = effect_spec(f.id);
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) start.push_back(spec.parameters[i].to_unit(f.values[i]));
  }
  if (start.empty()) return combined_variant(combination, values, nominal);
  // Unit space -> each effect's values.
  const auto values_at = [&combination](std::span<const double> x) {
    std::vector<std::vector<double>> v;
    std::size_t k = 0;
    for (const EffectFit& f : combination) {
      v.emplace_back();
      for (const ParameterSpec& p : effect_spec(f.id).parameters) v.back().push_back(p.from_unit(x[k++]));
    }
    return v;
  };
  const auto residuals = [&](Fidelity fidelity) -> optimize::ResidualFunction {
    return [&, fidelity](std::span<const double> x) -> std::optional<std::vector<double>> {
      try {
        return problem.training_residuals(
            problem.evaluate(combined_variant(combination, values_at(x), nominal), true, nullptr, fidelity));
      } catch (const std::exception&) {
        return std::nullopt;  // an unphysical corner of the ranges
      }
    };
  };
  optimize::LeastSquaresSettings settings{.lower = std::vector<double>(start.size(), 0.0),
                                          .upper = std::vector<double>(start.size(), 1.0),
                                          .difference_step = 0.005,
                                          .max_evaluations = options.joint_refit_evaluations,
                                          .jobs = options.jobs};
  if (problem.depends_on_step()) settings.difference_residuals = residuals(Fidelity::kCoarse);
  const optimize::LeastSquaresResult fit =
      optimize::minimize_least_squares(residuals(Fidelity::kFine), start, settings);
  values = values_at(fit.x);
  for (std::size_t e = 0; e < combination.size(); ++e) {
    combination[e].values = values[e];
    combination[e].params = describe_values(combination[e].id, values[e], nominal.device);
  }
  return combined_variant(combination, values, nominal);
}

}  // namespace softwrist::diagnosis
