#pragma once
/// The curve-edit stage (curve get-up seed §4.3, §6.2: the user authors a style by editing curves
/// and watching a trained policy follow them), as a search: each trial is one edit of a base curve
/// — its rise moved, one control point of h moved, its duration scaled — and runs a trained
/// policy on the edited curve from fixed starts (the same for every trial). Seconds per trial, so a
/// random or novelty search over edits shows which styles the policy can follow. Its figures are
/// the final test's (train_curves.h's CurveFollowing); its strategy features are the achieved
/// curves at the 9 knots t = T·j/8 (mean over the episodes): h in cm, θ_x and θ_z in degrees
/// (comparable steps: two trials are distinct styles when these 27 numbers lie more than
/// kEditStrategyThreshold apart).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/character/evaluator.h"
#include "style_curve.h"
#include "train_curves.h"

namespace podium::tasks::getup_curves {

/// The edit stage's keys (`edit_…`); the env and the test seed are the train stage's.
struct EditSettings {
  std::string base_curve = "faceup";  ///< the curve edited: a shipped name or a path (as `curves`)
  int point = 5;                      ///< the control point of h the `h_offset_m` param moves (0–8)
  int episodes = 0;                   ///< test episodes per trial (0: the train stage's test_starts)
  /// A shipped policy (TorchScript) run when no input train trial is given, acting through
  /// `shipped_cvae` when set (actions "cvae"), else on PD targets (the demo's authoring stage).
  std::string shipped_policy, shipped_cvae;
};
void read_edit_settings(base::ConfigReader& r, EditSettings& s);

/// One edit (the trial's params): applied as shift_rise, then move_control_point("h", point),
/// then scale_duration (curve_edit.h); each must leave a valid curve.
struct CurveEdit {
  /// The rise (curve_edit.h's rise_time_s) moved to this fraction of T (0: where it is). As a
  /// fraction the search space fits any base curve, where a shift in seconds could leave (0, T).
  double rise_fraction = 0.0;
  double h_offset_m = 0.0;      ///< h's control point `point` moved by this much
  double duration_scale = 1.0;  ///< T times this
};
/// The params' search space (describe()'s "params").
base::Json edit_params();
/// The edited curve, named "<base>+edit".
StyleCurve edited_curve(const StyleCurve& base, const CurveEdit& edit, int point);

/// What an edit trial measured.
struct EditOutcome {
  StyleCurve curve;              ///< the edited curve
  CurveTest test;                ///< its episodes (one curve: following[0])
  std::vector<double> features;  ///< h ×9, θ_x ×9, θ_z ×9 at the knots (cm, degrees), mean over the episodes
  std::filesystem::path curve_file, curves, trajectory;  ///< written in the work dir
};
/// The strategy threshold: 30 cm/° over the 27 knot values (about 6 per knot, RMS).
inline constexpr double kEditStrategyThreshold = 30.0;
/// The strategy features' descriptions (27, in EditOutcome::features' order).
base::Json edit_features();

/// Runs `policy` (observation ↦ action, fitting the env of `train`) on the edit of `settings`' base
/// curve from the test starts; writes the edited curve file, the first episode's motion and its
/// target-vs-achieved features (the train stage's `curves` format) to `work_dir`.
EditOutcome run_curve_edit(const TrainSettings& train, const EditSettings& settings, const CurveEdit& edit,
                           const character::PolicyFn& policy, const std::filesystem::path& work_dir);

}  // namespace podium::tasks::getup_curves
