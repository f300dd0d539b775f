// toolpoint study: the tip block from a tap test, with the model-based correction, and the tap
// test's FRFs picked from one universal file (studies/rotational.hpp).
#include "toolpoint/studies/rotational.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "toolpoint/error.hpp"

namespace toolpoint {

void TapTestFileOptions::check() const {
  check_fields(tap_test_file_fields(), *this, "TapTestFileOptions");
  const std::size_t points = static_cast<std::size_t>(order) + 1;
  if (nodes.size() < points)
    throw InvalidArgument(fmt::format("TapTestFileOptions::nodes gives {} node(s); order-{} differences need {} (the tip first)",
                                      nodes.size(), order, points),
                          "e.g. TapTestFileOptions::nodes 101,102,103");
  for (std::size_t a = 0; a < points; ++a)
    for (std::size_t b = a + 1; b < points; ++b)
      if (nodes[a] == nodes[b]) throw InvalidArgument(fmt::format("TapTestFileOptions::nodes names node {} twice", nodes[a]));
  if (direction && (*direction < -6 || *direction > 6))
    throw InvalidArgument(fmt::format("TapTestFileOptions::direction {} is no UFF direction code (−6…6)", *direction),
                          "e.g. 2 for +Y, −3 for −Z");
}

const std::vector<OptionField<TapTestFileOptions>>& tap_test_file_fields() {
  using O = TapTestFileOptions;
  static const std::vector<OptionField<O>> fields = {
      {with_help(option_field(rotational_fields(), "order").spec,
                 "the finite-difference order: order 2 reads points 0, 1, 2; order 1 points 0, 1"),
       nullptr, [](O& o) -> int& { return o.order; }}};
  return fields;
}

TapTestFileFrfs tap_test_frfs(const UffFile& file, const TapTestFileOptions& options) {
  options.check();
  const int points = options.order + 1;
  const std::vector<int> nodes(options.nodes.begin(), options.nodes.begin() + points);
  const auto point_of = [&](int node) {
    const auto it = std::find(nodes.begin(), nodes.end(), node);
    return it == nodes.end() ? -1 : static_cast<int>(it - nodes.begin());
  };
  const UffDataset58* used[3][3] = {};
  const UffDataset58* coherence[3][3] = {};
  std::string seen;  // the node pairs the file holds, for the message when the tip is missing
  std::size_t listed = 0;
  for (const UffDataset58& d : file.functions) {
    if (listed < 20)
      seen += fmt::format("{}{}/{} {}", listed ? ", " : "", d.response_node, d.reference_node,
                          uff_direction_name(d.response_direction));
    ++listed;
    const int i = point_of(d.response_node), j = point_of(d.reference_node);
    if (i < 0 || j < 0) continue;
    if (options.direction && (d.response_direction != *options.direction || d.reference_direction != *options.direction))
      continue;
    if (d.function_type == 6) {
      if (const UffDataset58* other = coherence[i][j])
        throw InputError(fmt::format("{}: datasets {} and {} are both coherences of response node {} and reference node {}",
                                     file.source, other->index, d.index, d.response_node, d.reference_node),
                         "pick the direction measured (TapTestFileOptions::direction), or keep one coherence per pair");
      coherence[i][j] = &d;
      continue;
    }
    if (const UffDataset58* other = used[i][j])
      throw InputError(fmt::format("{}: datasets {} and {} both have response node {} and reference node {} (directions "
                                   "{}/{} and {}/{})",
                                   file.source, other->index, d.index, d.response_node, d.reference_node,
                                   uff_direction_name(other->response_direction), uff_direction_name(other->reference_direction),
                                   uff_direction_name(d.response_direction), uff_direction_name(d.reference_direction)),
                       "pick the direction measured (TapTestFileOptions::direction, e.g. +Y), or keep one dataset per pair "
                       "of points");
    used[i][j] = &d;
  }
  if (listed > 20) seen += fmt::format(" … and {} more", listed - 20);
  if (!used[0][0])
    throw InputError(
        fmt::format("{}: no dataset with response and reference node {} (the tip: the first of TapTestFileOptions::nodes {}){}; "
                    "the file holds response/reference nodes {}",
                    file.source, nodes[0], fmt::join(options.nodes, ","),
                    options.direction ? fmt::format(" in direction {}", uff_direction_name(*options.direction)) : "",
                    seen.empty() ? "(none: no readable dataset 58)" : seen),
        "give the node numbers of the tip and the points inward, tip first, e.g. TapTestFileOptions::nodes 101,102,103");
  TapTestFileFrfs r;
  r.frfs.unread = file.skipped;
  for (int i = 0; i < points; ++i)
    for (int j = 0; j < points; ++j) {
      const UffDataset58* d = used[i][j];
      if (!d) continue;
      UffReceptance h = uff_receptance(*d, options.ordinate, file.source, options.units);
      r.warnings.insert(r.warnings.end(), h.warnings.begin(), h.warnings.end());
      r.frfs.set(i, j, std::move(h.receptance),
                 fmt::format("{} dataset {} (nodes {}/{})", file.source, d->index, d->response_node, d->reference_node));
      r.dataset[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = d->index;
      if (const UffDataset58* c = coherence[i][j]) {
        std::vector<double> g = uff_coherence_values(*c, file.source);
        if (g.size() != d->y.size())
          throw InputError(fmt::format("{}: the coherence (dataset {}) of nodes {}/{} has {} points, its FRF (dataset {}) {}",
                                       file.source, c->index, d->response_node, d->reference_node, g.size(), d->index,
                                       d->y.size()),
                           "export the coherence on the FRF's frequency lines");
        r.coherence[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = std::move(g);
      }
    }
  return r;
}

void RotationalStudyOptions::check() const { differences.check(); }

RotationalStudy run_rotational_study(const RotationalInput& input, const RotationalStudyOptions& options,
                                     const ProgressCallback& progress) {
  options.check();
  const RotationalOptions& o = options.differences;
  RotationalStudy r;
  r.order = o.order;
  r.spacing_m = o.spacing;
  r.differences = rotational_frfs(input.frfs, o);
  r.block = r.differences.block;
  if (progress) progress(input.model ? 0.2 : 1.0);
  r.correction_note = "no finite-difference correction";
  if (input.model) {
    FiniteDifferenceError e = finite_difference_error(*input.model, input.side, r.block.frequency_hz, input.frfs, o);
    r.block = remove_finite_difference_error(r.block, e);
    r.correction_note = fmt::format(
        "finite-difference error estimated on the model {} (points on the {}) and removed: at most {:.2g} % of |L|, "
        "{:.2g} % of |N|, {:.2g} % of |P|",
        input.model_name, tap_side_name(input.side), 100.0 * e.max_relative[1], 100.0 * e.max_relative[2],
        100.0 * e.max_relative[3]);
    r.warnings = e.warnings;
    r.correction = std::move(e);
    if (progress) progress(1.0);
  }
  const RotationalResult& d = r.differences;
  r.method = fmt::format(
      "tip block by order-{} finite differences (Duarte & Ewins), spacing s = {} m; points 0 (tip), 1, 2 at s, 2s inward; "
      "L and N {}; P {}",
      o.order, o.spacing,
      d.l_equals_n_by_reciprocity ? "from the same data (L = N by reciprocity)"
      : o.symmetrise              ? "symmetrised (their mean)"
                                  : "as measured (L from H0j, N from Hi0)",
      d.p_from_cross_terms ? "from cross terms" : "approximated as N*L/H00 (Schmitz & Smith)");
  r.reciprocity = d.filled_by_reciprocity.empty()
                      ? std::string("no measurement filled by reciprocity")
                      : fmt::format("reciprocity assumed (RotationalOptions::assume_reciprocity), not measured: {}",
                                    fmt::join(d.filled_by_reciprocity, ", "));
  r.warnings.insert(r.warnings.end(), d.warnings.begin(), d.warnings.end());
  return r;
}

plot::Figure rotational_figure(const RotationalStudy& study) {
  return plot::block_figure(study.block,
                            fmt::format("Tip block by order-{} finite differences, s = {:g} mm", study.order,
                                        1000.0 * study.spacing_m),
                            "00");
}

}  // namespace toolpoint
