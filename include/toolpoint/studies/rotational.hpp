// toolpoint study: the tip block [[H, L], [N, P]] from a tap test — the procedure behind
// `rotational`, as one library call: the translational FRFs at the tip and at points s, 2s inward
// differenced (Duarte & Ewins; signal.hpp's rotational_frfs), and, given a model of the structure
// tested, the differences' truncation error estimated on the model and removed
// (studies/fd_correction.hpp). Also here: the tap test's FRFs picked from one universal file by
// node and direction (what a measurement system writes).
// Units: SI (H m/N, L 1/N, N rad/N, P rad/(N·m)); spacing in m; frequencies in Hz.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "toolpoint/model/assembly.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/studies/fd_correction.hpp"
#include "toolpoint/studies/study.hpp"
#include "toolpoint/studies/tap_test.hpp"
#include "toolpoint/io/uff.hpp"

namespace toolpoint {

// ---- A tap test in one universal file ------------------------------------------------------------
//
// H_ij is the dataset 58 whose response node is point i's and whose reference node is point j's
// (`nodes`, tip first), in one direction (`direction`, or any when there is one per pair of
// points). Anything ambiguous is refused, naming the datasets.
struct TapTestFileOptions {
  std::vector<int> nodes{1, 2, 3};      // UFF node numbers of points 0 (the tip), 1, 2 (what run_tap_test_study's file holds)
  std::optional<int> direction;         // response and reference direction, record 6 code −6…6 (+Y = 2); unset: any
  int order = 2;                        // the finite-difference order: points 0…order are read
  std::optional<FrfOrdinate> ordinate;  // what the values are (frf_file.hpp); default: the datasets' codes
  std::optional<FrfUnits> units;        // the values' units; default: the file's
  // Throws InvalidArgument naming `TapTestFileOptions::<field>`: fewer nodes than points, a node
  // named twice, a direction code outside −6…6, an order other than 1 or 2 (tap_test_file_fields()).
  void check() const;
};

/// \brief TapTestFileOptions' scalar field defined once (option_fields.hpp): check() and Python's
/// tap_test_frfs keyword derive from this table (the nodes, the direction, the ordinate and the
/// units are checked beside it).
/// \return the table
const std::vector<OptionField<TapTestFileOptions>>& tap_test_file_fields();

struct TapTestFileFrfs {
  PointFrfs frfs;  // H_ij as receptance [m/N], sources "FILE dataset K (nodes a/b)"
  // The coherence γ² of H_ij where the file holds a dataset of function type 6 (coherence) for the
  // same nodes and direction (what averaging measurement software exports beside each FRF), on its
  // grid; empty otherwise. Coherence datasets are never taken for FRFs.
  std::array<std::array<std::vector<double>, 3>, 3> coherence;
  // The index (among the file's datasets 58, as UffFile::functions) each H_ij came from.
  std::array<std::array<std::optional<std::size_t>, 3>, 3> dataset{};
  std::vector<std::string> warnings;  // the conversions' (the file's own: file.warnings_for({}))
};

// The tap test's FRFs in `file` (read_uff). Throws InvalidArgument (options), InputError (two
// datasets for one pair of points, naming both; no dataset for the tip, listing the node pairs the
// file holds; a dataset that cannot be read as receptance).
TapTestFileFrfs tap_test_frfs(const UffFile& file, const TapTestFileOptions& options = {});

// ---- The study -----------------------------------------------------------------------------------

// What was measured, and optionally the model of what was measured.
struct RotationalInput {
  PointFrfs frfs;  // H_ij at the tip (0) and s, 2s inward (1, 2), on one grid
  // The structure tested: the same differences on its FRFs at the same points, against its exact
  // tip block, estimate the truncation error, which is removed (fd_correction.hpp). Unset: none.
  std::optional<Assembly> model;
  TapSide side = TapSide::Tool;          // where the points are on the model
  std::string model_name = "the model";  // names it in the description (a file name)
};

struct RotationalStudyOptions {
  RotationalOptions differences;  // order, spacing (no default), symmetrising, P, κGA, reciprocity
  void check() const;             // differences.check()
};

struct RotationalStudy {
  BlockSeries block;             // the tip block [[H00, L], [N, P]]: the differences, the error removed when corrected
  RotationalResult differences;  // the differences as computed (their block before any correction)
  std::optional<FiniteDifferenceError> correction;  // the error estimated on the model and removed
  int order = 2;                                    // the differences' order and spacing [m], as run
  double spacing_m = 0.0;
  // How the block was made, one line each (for a file's header or a report): the method (order,
  // spacing, where L, N and P came from), the reciprocity fills, the correction.
  std::string method, reciprocity, correction_note;
  std::vector<std::string> warnings;  // the correction's (the model's), then the differences'
};

// Runs the study. Throws InvalidArgument (options; points beyond the model's tool or holder),
// InputError (a needed H_ij missing, grids that differ, non-finite values), NumericalError, and
// what the model throws.
RotationalStudy run_rotational_study(const RotationalInput& input, const RotationalStudyOptions& options,
                                     const ProgressCallback& progress = {});

// The block's four entries (plot::block_figure), titled with the order and the spacing [mm].
plot::Figure rotational_figure(const RotationalStudy& study);

}  // namespace toolpoint
