// toolpoint: a joint's uncertainty carried to the tool point FRF and to stability (uncertainty.hpp).
#include "toolpoint/uncertainty/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include <Eigen/Eigenvalues>

#include "toolpoint/error.hpp"
#include "toolpoint/measured/noise.hpp"
#include "toolpoint/measured/signal.hpp"

namespace toolpoint {

std::vector<JointParameters> sample_joints(const JointParameters& mean, const Eigen::Matrix<double, 8, 8>& covariance, int count,
                                           std::uint64_t seed) {
  if (count < 1) throw InvalidArgument(fmt::format("sample_joints: count = {} must be ≥ 1", count));
  if (!covariance.allFinite()) throw InvalidArgument("sample_joints: the covariance is not finite");
  mean.check();
  // Eigen-decompose the correlation matrix (entries of the covariance span many decades in SI
  // units), then scale back: C = D R D, R = V Λ Vᵀ, x = θ̂ + D V √Λ z.
  Eigen::Matrix<double, 8, 1> d;
  for (int i = 0; i < 8; ++i) d(i) = std::sqrt(std::max(0.0, covariance(i, i)));
  Eigen::Matrix<double, 8, 8> r = Eigen::Matrix<double, 8, 8>::Identity();
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      if (d(i) > 0.0 && d(j) > 0.0) r(i, j) = covariance(i, j) / (d(i) * d(j));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 8, 8>> es(r);
  if (es.eigenvalues()(0) < -1e-6)
    throw InvalidArgument(
        fmt::format("sample_joints: the covariance is not positive semidefinite (correlation eigenvalue {:.3g})",
                    es.eigenvalues()(0)));
  const Eigen::Matrix<double, 8, 8> root = d.asDiagonal() * es.eigenvectors() *
                                           es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  std::vector<JointParameters> out;
  out.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const std::vector<double> z = standard_normals(8, stream_seed(seed, static_cast<std::uint64_t>(i)));
    const Eigen::Matrix<double, 8, 1> x = root * Eigen::Map<const Eigen::Matrix<double, 8, 1>>(z.data());
    JointParameters p = mean;
    for (int k = 0; k < 8; ++k) p[k] += x(k);
    out.push_back(p);
  }
  return out;
}

void UncertaintyOptions::check() const {
  check_fields(uncertainty_fields(), *this, "UncertaintyOptions");
  if (levels.empty()) throw InvalidArgument("UncertaintyOptions::levels is empty");
  for (std::size_t i = 0; i < levels.size(); ++i)
    if (!(levels[i] > 0.0 && levels[i] < 1.0) || (i > 0 && !(levels[i] > levels[i - 1])))
      throw InvalidArgument(
          fmt::format("UncertaintyOptions::levels must increase within (0, 1); level {} is {}", i + 1, levels[i]));
}

const std::vector<OptionField<UncertaintyOptions>>& uncertainty_fields() {
  using O = UncertaintyOptions;
  static const std::vector<OptionField<O>> fields = {
      {{.name = "samples",
        .kind = FieldKind::Integer,
        .min = 10.0,
        .max = 1e6,
        .help = "joints drawn from the joint's covariance (200 put the 5 % and 95 % quantiles within about ±2 % in "
                "probability)",
        .cli_name = "samples"},
       nullptr,
       [](O& o) -> int& { return o.samples; }},
      {option_field(parallel_fields(), "threads").spec, nullptr, [](O& o) -> int& { return o.parallel.threads; }}};
  return fields;
}

namespace {

const JointUncertainty& uncertainty_of(const JointFile& joint) {
  if (!joint.uncertainty)
    throw InvalidArgument(fmt::format("{}: the joint file has no [uncertainty]: nothing to sample",
                                      joint.source.empty() ? "joint" : joint.source),
                          "write a band-fitted joint with write_joint_file: the fit's covariance is its [uncertainty]");
  return *joint.uncertainty;
}

// Quantiles of |H| and ∠H over the samples' FRFs, the phase taken relative to the nominal's so
// that it does not wrap.
FrfBand band_of(const std::vector<FrfSeries>& samples, FrfSeries nominal, const std::vector<double>& levels) {
  FrfBand b;
  b.frequency_hz = nominal.frequency_hz;
  b.levels = levels;
  b.samples = static_cast<int>(samples.size());
  const std::size_t n = nominal.size();
  b.magnitude.assign(levels.size(), std::vector<double>(n));
  b.phase_rad.assign(levels.size(), std::vector<double>(n));
  std::vector<double> mag(samples.size()), ph(samples.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Complex h0 = nominal.values[i];
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const Complex h = samples[s].values[i];
      mag[s] = std::abs(h);
      ph[s] = std::arg(h0) + std::arg(h / h0);
    }
    for (std::size_t l = 0; l < levels.size(); ++l) {
      b.magnitude[l][i] = quantile(mag, levels[l]);
      b.phase_rad[l][i] = quantile(ph, levels[l]);
    }
  }
  b.nominal = std::move(nominal);
  return b;
}

// The FRF of every sampled joint, on every core.
std::vector<FrfSeries> sampled_frfs(const Assembly& assembly, const JointFile& joint, const UncertaintyOptions& o,
                                    const std::function<FrfSeries(const Assembly&)>& frf) {
  const JointUncertainty& u = uncertainty_of(joint);
  const std::vector<JointParameters> joints = sample_joints(joint.parameters, u.covariance, o.samples, o.seed);
  std::vector<FrfSeries> out(joints.size());
  parallel_for(
      joints.size(), o.parallel,
      [&](std::size_t i) {
        JointFile ji = joint;
        ji.parameters = joints[i];
        out[i] = frf(with_joint(assembly, ji));
      },
      o.progress);
  return out;
}

}  // namespace

FrfBand tool_point_band(const Assembly& assembly, const JointFile& joint, const std::vector<double>& frequency_hz,
                        const UncertaintyOptions& o) {
  o.check();
  auto frf = [&](const Assembly& a) { return entry(AssemblyModel(a).tool_point(frequency_hz), 0); };
  const auto samples = sampled_frfs(assembly, joint, o, frf);
  return band_of(samples, frf(with_joint(assembly, joint)), o.levels);
}

FrfBand coupled_tool_point_band(const Assembly& assembly, const JointFile& joint, const BlockSeries& sh11,
                                const std::string& sh_name, const UncertaintyOptions& o) {
  o.check();
  if (joint.interface != JointInterface::HolderTool)
    throw InvalidArgument(
        fmt::format("{}: coupling a measured SH11 to the tool needs the holder–tool joint, the file holds the {} joint",
                    joint.source, to_string(joint.interface)));
  auto frf = [&](const Assembly& a) { return entry(couple_tool(a, sh11, sh_name), 0); };
  const auto samples = sampled_frfs(assembly, joint, o, frf);
  return band_of(samples, frf(with_joint(assembly, joint)), o.levels);
}

namespace {

// Quantiles and the probability map from each sample's envelope on the common speed grid.
StabilityUncertainty summarise(std::vector<double> speeds, std::vector<double> nominal,
                               const std::vector<std::vector<double>>& depth, const std::vector<double>& depth_grid_m,
                               const std::vector<double>& levels) {
  StabilityUncertainty r;
  r.speed_rpm = std::move(speeds);
  r.nominal_depth_m = std::move(nominal);
  r.levels = levels;
  r.samples = static_cast<int>(depth.size());
  r.depth_grid_m = depth_grid_m;
  const std::size_t ns = r.speed_rpm.size();
  r.depth_m.assign(levels.size(), std::vector<double>(ns));
  r.probability = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(ns), static_cast<Eigen::Index>(depth_grid_m.size()));
  std::vector<double> at(depth.size());
  for (std::size_t k = 0; k < ns; ++k) {
    for (std::size_t s = 0; s < depth.size(); ++s) at[s] = depth[s].at(k);
    for (std::size_t l = 0; l < levels.size(); ++l) r.depth_m[l][k] = quantile(at, levels[l]);
    std::sort(at.begin(), at.end());
    for (std::size_t j = 0; j < depth_grid_m.size(); ++j) {
      // Stable at depth a when the sample's envelope lies above a.
      const auto above = at.end() - std::upper_bound(at.begin(), at.end(), depth_grid_m[j]);
      r.probability(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = static_cast<double>(above) /
                                                                                  static_cast<double>(at.size());
    }
  }
  return r;
}

void check_depth_grid(const std::vector<double>& depth_grid_m) {
  if (depth_grid_m.empty()) throw InvalidArgument("stability_uncertainty: the depth grid is empty");
  for (std::size_t i = 0; i < depth_grid_m.size(); ++i)
    if (!(depth_grid_m[i] >= 0.0 && std::isfinite(depth_grid_m[i])) || (i > 0 && !(depth_grid_m[i] > depth_grid_m[i - 1])))
      throw InvalidArgument("stability_uncertainty: the depth grid must increase from ≥ 0 m");
}

}  // namespace

// Every sample's envelope through `envelope`, on every core; the nominal's last.
StabilityUncertainty envelope_uncertainty(const Assembly& assembly, const JointFile& joint,
                                          const std::function<StabilityEnvelope(const Assembly&)>& envelope,
                                          const std::vector<double>& depth_grid_m, const UncertaintyOptions& o) {
  o.check();
  check_depth_grid(depth_grid_m);
  const JointUncertainty& u = uncertainty_of(joint);
  const std::vector<JointParameters> joints = sample_joints(joint.parameters, u.covariance, o.samples, o.seed);
  std::vector<std::vector<double>> depth(joints.size());
  parallel_for(
      joints.size(), o.parallel,
      [&](std::size_t i) {
        JointFile ji = joint;
        ji.parameters = joints[i];
        depth[i] = envelope(with_joint(assembly, ji)).second;
      },
      o.progress);
  auto [speeds, nominal] = envelope(with_joint(assembly, joint));
  return summarise(std::move(speeds), std::move(nominal), depth, depth_grid_m, o.levels);
}

StabilityUncertainty stability_uncertainty(const Assembly& assembly, const JointFile& joint,
                                           const std::vector<double>& frequency_hz, const CuttingConditions& cutting,
                                           const ZeroOrderOptions& lobes, const std::vector<double>& depth_grid_m,
                                           const UncertaintyOptions& o) {
  o.check();
  cutting.check();
  lobes.check();
  const auto envelope = [&](const Assembly& a) {
    MillingFrfs m;
    m.xx = entry(AssemblyModel(a).tool_point(frequency_hz), 0);
    const ZeroOrderResult z = zero_order_lobes(m, cutting, lobes);
    std::vector<double> d;
    for (const EnvelopePoint& p : z.envelope) d.push_back(p.depth_m);
    return StabilityEnvelope{lobes.speeds.values(), d};
  };
  return envelope_uncertainty(assembly, joint, envelope, depth_grid_m, o);
}

}  // namespace toolpoint
