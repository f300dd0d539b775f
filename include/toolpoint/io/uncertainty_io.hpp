// toolpoint: the results of uncertainty.hpp as tables (CSV) and figure data — its I/O layer, as
// stability_io.hpp is of stability.hpp.
//
// Units (in the column names): frequency Hz, |H| m/N, ∠H degrees (unwrapped around the nominal),
// spindle speed rpm, axial depth mm, probability 0…1.
#pragma once

#include <string>
#include <vector>

#include "toolpoint/io/io.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/uncertainty/uncertainty.hpp"

namespace toolpoint {

// The tool point FRF's quantiles: frequency_hz, magnitude_q<level %>_m_per_n per level, then
// phase_q<level %>_deg per level.
Table band_table(const FrfBand& band);

// FRF traces of the band for plot::frf_figure: the nominal ("identified joint", a line), then each
// quantile level but the median (magnitude and phase quantiles recombined), dashed.
std::vector<plot::FrfTrace> band_traces(const FrfBand& band);

// The probability of stability, one row per (speed, depth), speed slowest:
// spindle_speed_rpm, axial_depth_mm, probability_stable.
Table probability_table(const StabilityUncertainty& stability);

// The quantile envelopes as extra curves of a lobes figure (plot::LobesFigureData::other_envelopes):
// level q is "stable in (1 − q) of N joints" (the first naming the sample count N, the others "of them").
std::vector<plot::LobesFigureData::Envelope> quantile_envelopes(const StabilityUncertainty& stability);

// The probability map as figure data (plot::probability_map_figure) on the envelope's speeds and the
// map's depths, with the nominal envelope and the lowest level's ("stable with 95 % probability")
// on top; `joint_source` names the sampled joint in the title.
plot::ProbabilityMapData probability_map(const StabilityUncertainty& stability, const std::string& joint_source);

}  // namespace toolpoint
