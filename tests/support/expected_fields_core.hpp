// The option tables of the Options types every stage shares — ParallelOptions, UncertaintyOptions,
// ZeroOrderOptions, BoundaryOptions, ModalOptions, BeamStudyOptions, PredictOptions,
// OverhangStudyOptions, CuttingConditions, SpeedRange, NoiseSpec, ForceLaw, Cutter, MillingCut,
// DepthRange (option_fields.hpp;
// issue 26) — expected by hand: each field's range as the hand-written check() had it before its
// table (parallel.cpp, uncertainty.cpp, stability.cpp, beam.cpp, studies/beam.cpp, studies/predict.cpp,
// studies/overhang.cpp at b7606b0), and its flag and unit as `toolpoint lobes`, `beam`, `predict` and the commands with
// --threads and --samples registered them — not read from the tables (expected_fields.hpp's
// expect_edges and expect_table).
#pragma once

#include <limits>
#include <vector>

#include "support/expected_fields.hpp"
#include "toolpoint/model/beam.hpp"
#include "toolpoint/parallel.hpp"
#include "toolpoint/stability/simulation.hpp"
#include "toolpoint/stability/stability.hpp"
#include "toolpoint/studies/beam.hpp"
#include "toolpoint/studies/identification.hpp"
#include "toolpoint/studies/overhang.hpp"
#include "toolpoint/studies/predict.hpp"
#include "toolpoint/studies/simulation.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint::testing {

// Old ParallelOptions::check: threads < 0 or > 1024 refused. Every command's --threads.
inline std::vector<ExpectedField<ParallelOptions>> parallel_expected_fields() {
  using P = ParallelOptions;
  return {{"ParallelOptions", "threads", true, 0.0, 1024.0, false, false, 2.0, "--threads", "-", 1.0, "",
           TOOLPOINT_MEMBER(P, threads)}};
}

// Old UncertaintyOptions::check: samples outside 10…1000000 refused, then parallel.check() (named
// ParallelOptions::threads then, UncertaintyOptions::threads now). --samples, --threads.
inline std::vector<ExpectedField<UncertaintyOptions>> uncertainty_expected_fields() {
  using U = UncertaintyOptions;
  return {{"UncertaintyOptions", "samples", true, 10.0, 1e6, false, false, 50.0, "--samples", "-", 1.0, "",
           TOOLPOINT_MEMBER(U, samples)},
          {"UncertaintyOptions", "threads", true, 0.0, 1024.0, false, false, 3.0, "--threads", "-", 1.0, "",
           TOOLPOINT_MEMBER(U, parallel.threads)}};
}

// Old ZeroOrderOptions::check: lobes below −1 (automatic) or above 5000 refused; max_depth_m < 0 or
// not finite refused. `toolpoint lobes --lobes`, `--max-depth` [mm].
inline std::vector<ExpectedField<ZeroOrderOptions>> zero_order_expected_fields() {
  using Z = ZeroOrderOptions;
  return {{"ZeroOrderOptions", "lobes", true, -1.0, 5000.0, false, false, 20.0, "--lobes", "-", 1.0, "",
           TOOLPOINT_MEMBER(Z, lobes)},
          {"ZeroOrderOptions", "max_depth_m", false, 0.0, kInf, false, false, 0.005, "--max-depth", "mm", 1e3, "",
           TOOLPOINT_MEMBER(Z, max_depth_m)}};
}

// Old BoundaryOptions::check, with Discretization::Full and max_steps 20000: tolerance outside
// 1e-6…0.5 refused; steps 1…3 or above max_steps/2 = 10000 refused (0: automatic); max_steps
// outside 8…20000 refused; degree outside 1…3 refused; max_depth_m < 0 refused; then
// parallel.check(). `toolpoint lobes --tolerance` [%], `--intervals`, `--max-depth` [mm], `--threads`.
inline std::vector<ExpectedField<BoundaryOptions>> boundary_expected_fields() {
  using B = BoundaryOptions;
  return {{"BoundaryOptions", "tolerance", false, 1e-6, 0.5, false, false, 0.02, "--tolerance", "%", 100.0, "",
           TOOLPOINT_MEMBER(B, tolerance)},
          {"BoundaryOptions", "steps", true, 4.0, 10000.0, false, false, 40.0, "--intervals", "-", 1.0, "",
           TOOLPOINT_MEMBER(B, steps)},
          {"BoundaryOptions", "max_steps", true, 8.0, 20000.0, false, false, 1000.0, "", "", 1.0, "",
           TOOLPOINT_MEMBER(B, max_steps)},
          {"BoundaryOptions", "degree", true, 1.0, 3.0, false, false, 1.0, "", "", 1.0, "", TOOLPOINT_MEMBER(B, degree)},
          {"BoundaryOptions", "max_depth_m", false, 0.0, kInf, false, false, 0.005, "--max-depth", "mm", 1e3, "",
           TOOLPOINT_MEMBER(B, max_depth_m)},
          {"BoundaryOptions", "threads", true, 0.0, 1024.0, false, false, 2.0, "--threads", "-", 1.0, "",
           TOOLPOINT_MEMBER(B, parallel.threads)}};
}

// Old ModalOptions::check: modes outside 1…20000 refused. `toolpoint beam --modal-terms`,
// `--static-residual`.
inline std::vector<ExpectedField<ModalOptions>> modal_expected_fields() {
  using M = ModalOptions;
  return {{"ModalOptions", "modes", true, 1.0, 20000.0, false, false, 50.0, "--modal-terms", "-", 1.0, "",
           TOOLPOINT_MEMBER(M, modes)},
          {"ModalOptions", "static_residual", false, -kInf, kInf, false, false, 1.0, "--static-residual", "-", 1.0, "",
           TOOLPOINT_MEMBER(M, static_residual)}};
}

// Old: BeamStudyOptions::check refused modes outside 0…20000 and a speed < 0; Segment::check refused
// a length or an outer diameter ≤ 0 and an inner diameter < 0. `toolpoint beam --length` [m],
// `--diameter` [m], `--inner-diameter` [m], `--modes`, `--speed` [rpm].
inline std::vector<ExpectedField<BeamStudyOptions>> beam_study_expected_fields() {
  using B = BeamStudyOptions;
  return {{"BeamStudyOptions", "length", false, 0.0, kInf, true, false, 0.12, "--length", "m", 1.0, "",
           TOOLPOINT_MEMBER(B, length)},
          {"BeamStudyOptions", "outer_diameter", false, 0.0, kInf, true, false, 0.016, "--diameter", "m", 1.0, "",
           TOOLPOINT_MEMBER(B, outer_diameter)},
          {"BeamStudyOptions", "inner_diameter", false, 0.0, kInf, false, false, 0.008, "--inner-diameter", "m", 1.0, "",
           TOOLPOINT_MEMBER(B, inner_diameter)},
          {"BeamStudyOptions", "modes", true, 0.0, 20000.0, false, false, 8.0, "--modes", "-", 1.0, "",
           TOOLPOINT_MEMBER(B, modes)},
          {"BeamStudyOptions", "speed_rpm", false, 0.0, kInf, false, false, 20000.0, "--speed", "rpm", 1.0, "",
           TOOLPOINT_MEMBER(B, speed_rpm)}};
}

// Old PredictOptions::check: speed_rpm < 0 or not finite refused (and one that cannot be rpm).
// `toolpoint predict --speed` [rpm], `--extrapolate-bearings`.
inline std::vector<ExpectedField<PredictOptions>> predict_expected_fields() {
  using P = PredictOptions;
  return {{"PredictOptions", "speed_rpm", false, 0.0, kInf, false, false, 12000.0, "--speed", "rpm", 1.0, "",
           TOOLPOINT_MEMBER(P, speed_rpm)},
          {"PredictOptions", "extrapolate_bearings", false, -kInf, kInf, false, false, 1.0, "--extrapolate-bearings", "-",
           1.0, "", TOOLPOINT_MEMBER(P, extrapolate_bearings)}};
}

// Old OverhangStudyOptions::check: tracking_tolerance outside (0, 1) refused, threads outside
// 0…1024 refused. `toolpoint couple --threads` (the sweep's threads since the table; the samples'
// before).
inline std::vector<ExpectedField<OverhangStudyOptions>> overhang_study_expected_fields() {
  using O = OverhangStudyOptions;
  return {{"OverhangStudyOptions", "tracking_tolerance", false, 0.0, 1.0, true, true, 0.2, "", "", 1.0, "",
           TOOLPOINT_MEMBER(O, tracking_tolerance)},
          {"OverhangStudyOptions", "threads", true, 0.0, 1024.0, false, false, 2.0, "--threads", "-", 1.0, "",
           TOOLPOINT_MEMBER(O, threads)}};
}

// Old CuttingConditions::check (stability.cpp at 0c87010): teeth outside 1…1000 refused; K_t ≤ 0
// refused; K_r < 0 refused; diameter_m < 0 refused (0: not given); process damping < 0 or outside
// 1e3…1e8 N/m refused (0: none); helix_slices outside 0…200 refused (0: 8). The feed per tooth was
// judged only with runout (> 0); its range now is PlanOptions::feed_per_tooth_m's top 1 cm with 0
// "not given". `toolpoint lobes --teeth`, `--kt` [N/m²], `--kr`, `--feed` [mm], `--diameter` [mm],
// `--process-damping` [N/m]; the plan file's [cut] teeth, tangential_coefficient, radial_ratio,
// process_damping (docs/planning.md).
inline std::vector<ExpectedField<CuttingConditions>> cutting_expected_fields() {
  using C = CuttingConditions;
  const std::string t = "CuttingConditions";
  return {{t, "teeth", true, 1.0, 1000.0, false, false, 3.0, "--teeth", "-", 1.0, "cut.teeth", TOOLPOINT_MEMBER(C, teeth)},
          {t, "tangential_coefficient", false, 0.0, kInf, true, false, 2e9, "--kt", "N/m²", 1.0, "cut.tangential_coefficient",
           TOOLPOINT_MEMBER(C, tangential_coefficient)},
          {t, "radial_ratio", false, 0.0, kInf, false, false, 0.45, "--kr", "-", 1.0, "cut.radial_ratio",
           TOOLPOINT_MEMBER(C, radial_ratio)},
          {t, "feed_per_tooth_m", false, 0.0, 0.01, false, false, 2e-4, "--feed", "mm", 1e3, "",
           TOOLPOINT_MEMBER(C, feed_per_tooth_m)},
          {t, "diameter_m", false, 0.0, kInf, false, false, 0.016, "--diameter", "mm", 1e3, "", TOOLPOINT_MEMBER(C, diameter_m)},
          {t, "process_damping_n_per_m", false, 1e3, 1e8, false, false, 2e5, "--process-damping", "N/m", 1.0,
           "cut.process_damping", TOOLPOINT_MEMBER(C, process_damping_n_per_m)},
          {t, "helix_slices", true, 0.0, 200.0, false, false, 12.0, "", "", 1.0, "", TOOLPOINT_MEMBER(C, helix_slices)}};
}

// Old SpeedRange::check: min ≤ 0, max ≤ min, either not finite, points outside 2…1000000 refused.
// `toolpoint lobes --speeds`; the plan file's [machine] speed_min, speed_max, speed_points.
inline std::vector<ExpectedField<SpeedRange>> speed_range_expected_fields() {
  using S = SpeedRange;
  return {{"SpeedRange", "min_rpm", false, 0.0, kInf, true, false, 6000.0, "", "", 1.0, "machine.speed_min",
           TOOLPOINT_MEMBER(S, min_rpm)},
          {"SpeedRange", "max_rpm", false, 0.0, kInf, true, false, 18000.0, "", "", 1.0, "machine.speed_max",
           TOOLPOINT_MEMBER(S, max_rpm)},
          {"SpeedRange", "points", true, 2.0, 1e6, false, false, 50.0, "--speeds", "-", 1.0, "machine.speed_points",
           TOOLPOINT_MEMBER(S, points)}};
}

// Old NoiseSpec::check (studies/identification.cpp at ee078f9) and StatedNoise::check (noise.cpp):
// the stated σ's and floor outside 0…0.5 refused, the calibration outside 0…0.1, the averages
// outside 0…100000. `toolpoint identify --sigma`, `--phase-sigma` [degrees: the flag's old top
// 28.6° is 0.5 rad], `--floor`, `--calibration`, `--averages`.
inline std::vector<ExpectedField<NoiseSpec>> noise_spec_expected_fields() {
  using N = NoiseSpec;
  constexpr double kDeg = 57.295779513082323;  // degrees per radian
  const std::string t = "NoiseSpec";
  return {{t, "magnitude_sigma", false, 0.0, 0.5, false, false, 0.03, "--sigma", "-", 1.0, "",
           TOOLPOINT_MEMBER(N, magnitude_sigma)},
          {t, "phase_sigma_rad", false, 0.0, 0.5, false, false, 0.02, "--phase-sigma", "degrees", kDeg, "",
           TOOLPOINT_MEMBER(N, phase_sigma_rad)},
          {t, "floor", false, 0.0, 0.5, false, false, 0.01, "--floor", "-", 1.0, "", TOOLPOINT_MEMBER(N, floor)},
          {t, "calibration", false, 0.0, 0.1, false, false, 0.02, "--calibration", "-", 1.0, "",
           TOOLPOINT_MEMBER(N, calibration)},
          {t, "averages", true, 0.0, 100000.0, false, false, 30.0, "--averages", "-", 1.0, "", TOOLPOINT_MEMBER(N, averages)}};
}

// Old ForceLaw::check (simulation.cpp at eeda478): K_t ≤ 0, K_r < 0, K_te < 0, K_re < 0, x outside
// (0, 1], h₀ ≤ 0 refused; C_i 0 or within 1e3…1e8 N/m. `toolpoint simulate --kt`, `--kr`, `--kte`,
// `--kre` [N/m], `--exponent`, `--reference-chip` [mm], `--process-damping` [N/m].
inline std::vector<ExpectedField<ForceLaw>> force_law_expected_fields() {
  using F = ForceLaw;
  const std::string t = "ForceLaw";
  return {{t, "tangential_coefficient", false, 0.0, kInf, true, false, 2e9, "--kt", "N/m²", 1.0, "",
           TOOLPOINT_MEMBER(F, tangential_coefficient)},
          {t, "radial_ratio", false, 0.0, kInf, false, false, 0.3, "--kr", "-", 1.0, "", TOOLPOINT_MEMBER(F, radial_ratio)},
          {t, "tangential_edge", false, 0.0, kInf, false, false, 2e4, "--kte", "N/m", 1.0, "",
           TOOLPOINT_MEMBER(F, tangential_edge)},
          {t, "radial_edge", false, 0.0, kInf, false, false, 1e4, "--kre", "N/m", 1.0, "", TOOLPOINT_MEMBER(F, radial_edge)},
          {t, "exponent", false, 0.0, 1.0, true, false, 0.7, "--exponent", "-", 1.0, "", TOOLPOINT_MEMBER(F, exponent)},
          {t, "reference_chip_m", false, 0.0, kInf, true, false, 5e-5, "--reference-chip", "mm", 1e3, "",
           TOOLPOINT_MEMBER(F, reference_chip_m)},
          {t, "process_damping_n_per_m", false, 1e3, 1e8, false, false, 2e5, "--process-damping", "N/m", 1.0, "",
           TOOLPOINT_MEMBER(F, process_damping_n_per_m)}};
}

// Old Cutter::check, MillingCut::check (simulation.cpp at 2ae8d46) and DepthRange::check
// (studies/simulation.cpp): D ≤ 0 refused; helix outside 0…80° refused; flute length < 0 refused
// (0: not checked); n ≤ 0, a < 0, c < 0 refused (c's top now the cut's 10 mm); depths 0 < MIN < MAX,
// points 2…100000. `toolpoint simulate --diameter`, `--flute-length`, `--feed` [mm], `simulate map
// --depths`.
inline std::vector<ExpectedField<Cutter>> cutter_expected_fields() {
  using C = Cutter;
  constexpr double k80 = 80.0 * 3.14159265358979323846 / 180.0;  // 80° [rad]
  return {{"Cutter", "diameter_m", false, 0.0, kInf, true, false, 0.016, "--diameter", "mm", 1e3, "",
           TOOLPOINT_MEMBER(C, diameter_m)},
          {"Cutter", "helix_rad", false, 0.0, k80, false, false, 0.5, "", "", 1.0, "", TOOLPOINT_MEMBER(C, helix_rad)},
          {"Cutter", "flute_length_m", false, 0.0, kInf, false, false, 0.03, "--flute-length", "mm", 1e3, "",
           TOOLPOINT_MEMBER(C, flute_length_m)}};
}

inline std::vector<ExpectedField<MillingCut>> milling_cut_expected_fields() {
  using M = MillingCut;
  return {{"MillingCut", "speed_rpm", false, 0.0, kInf, true, false, 12000.0, "", "", 1.0, "", TOOLPOINT_MEMBER(M, speed_rpm)},
          {"MillingCut", "depth_m", false, 0.0, kInf, false, false, 0.002, "", "", 1.0, "", TOOLPOINT_MEMBER(M, depth_m)},
          {"MillingCut", "feed_per_tooth_m", false, 0.0, 0.01, false, false, 1e-4, "--feed", "mm", 1e3, "",
           TOOLPOINT_MEMBER(M, feed_per_tooth_m)}};
}

inline std::vector<ExpectedField<DepthRange>> depth_range_expected_fields() {
  using D = DepthRange;
  return {{"DepthRange", "min_m", false, 0.0, kInf, true, false, 5e-4, "", "", 1.0, "", TOOLPOINT_MEMBER(D, min_m)},
          {"DepthRange", "max_m", false, 0.0, kInf, true, false, 0.004, "", "", 1.0, "", TOOLPOINT_MEMBER(D, max_m)},
          {"DepthRange", "points", true, 2.0, 100000.0, false, false, 30.0, "--depths", "-", 1.0, "",
           TOOLPOINT_MEMBER(D, points)}};
}

}  // namespace toolpoint::testing
