// toolpoint rotational: the tip block [[H, L], [N, P]] from translational FRFs measured at the
// tip and at points s and 2s inward, by Duarte & Ewins finite differences (seed Section 4).
// Units: spacing in m; FRFs in m/N in, block out in m/N, 1/N, rad/N, rad/(N·m); frequencies Hz.
// --plot draws the four entries of the block written.
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/uff.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/studies/rotational.hpp"

namespace toolpoint::cli {

namespace {

struct RotationalCliOptions {
  double shear_stiffness = 0.0;
  std::string files[3][3];  // files[i][j]: H_ij, response at point i, force at point j
  std::string output, p_method = "auto", plot, uff, direction;
  std::string model, at_site;  // --model A.toml --at tool|holder: the model-based correction
  std::vector<int> nodes;      // --nodes: UFF node numbers of points 0 (tip), 1, 2
  RotationalOptions fd;
  FieldFlags<RotationalOptions> fields;  // --order, --symmetrise, --assume-reciprocity (rotational_fields)
};

void run_rotational(RotationalCliOptions o, const Globals& g) {
  o.fields.apply(o.fd);
  o.fd.p_method = o.p_method == "cross" ? PMethod::CrossTerms : o.p_method == "n2h" ? PMethod::SchmitzSmith : PMethod::Auto;
  o.fd.check();
  check_plot_path(o.plot);
  {
    std::vector<RunPath> inputs{{o.uff, "--uff"}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) inputs.push_back({o.files[i][j], fmt::format("--h{}{}", i, j)});
    check_paths(inputs, {{o.output, "--output"}, {o.plot, "--plot"}});
  }
  check_output_extension(o.output, "--output", {".csv"}, kBlockCsvOutput);
  RotationalInput in;
  std::string sources;
  std::vector<double> tip_coherence;  // of H00, the block's H, written beside it
  if (!o.uff.empty()) {
    for (const auto& f : o.files)
      for (const auto& name : f)
        if (!name.empty()) throw InvalidArgument("give either --uff or --hij files, not both", "use --uff for one tap-test file");
    // H_ij: the dataset whose response node is point i's and whose reference node is point j's.
    const UffFile file = read_uff(o.uff);
    warn_all(file.warnings_for({}));
    TapTestFileOptions t;
    if (!o.nodes.empty()) t.nodes = o.nodes;
    if (!o.direction.empty()) t.direction = parse_uff_direction(o.direction, "--direction");
    t.order = o.fd.order;
    const FrfReadOptions read = frf_read_options(g.frf);
    if (read.csv.format || !read.csv.columns.empty())
      throw InvalidArgument("--format and --columns apply to CSV inputs, not to --uff", "drop them");
    t.ordinate = read.ordinate;
    t.units = read.units;
    TapTestFileFrfs tap = tap_test_frfs(file, t);
    warn_all(tap.warnings);
    in.frfs = std::move(tap.frfs);
    tip_coherence = std::move(tap.coherence[0][0]);
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j)
        if (tap.dataset[i][j]) sources += fmt::format(" H{}{}={}#{}", i, j, o.uff, *tap.dataset[i][j]);
  } else if (!o.nodes.empty() || !o.direction.empty()) {
    throw InvalidArgument("--nodes and --direction select datasets of a --uff file", "give --uff FILE, or drop them");
  }
  if (o.uff.empty() && o.files[0][0].empty())
    throw InvalidArgument("rotational needs the tip FRF: --h00 FILE (and the others), or --uff FILE with the whole test",
                          "see `toolpoint rotational --help`");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!o.files[i][j].empty()) {
        FrfFileData d = read_frf_input(g, o.files[i][j]);
        if (d.is_block)
          throw InputError(fmt::format("--h{}{} {}: holds a 2×2 block, expected a single translational FRF H{}{} [m/N]", i, j,
                                       o.files[i][j], i, j),
                           "give the measured FRF (frequency_hz,re,im CSV, a UFF dataset or a .frf file)");
        if (i == 0 && j == 0) tip_coherence = std::move(d.coherence);
        in.frfs.set(i, j, std::move(d.single), o.files[i][j]);
        sources += fmt::format(" H{}{}={}", i, j, o.files[i][j]);
      }
  RotationalStudyOptions so;
  so.differences = o.fd;
  if (o.shear_stiffness != 0.0) so.differences.shear_stiffness = o.shear_stiffness;
  if (o.model.empty() != o.at_site.empty())
    throw InvalidArgument("--model and --at go together: the assembly model and where on it the points are",
                          "add --at tool (points on the tool, for SHT11) or --at holder (on the holder, for SH11)");
  if (!o.model.empty()) {
    LoadedAssembly model = load_assembly(o.model);
    warn_all(model.warnings);
    in.model = std::move(model.assembly);
    in.side = o.at_site == "holder" ? TapSide::Holder : TapSide::Tool;
    in.model_name = o.model;
  }
  const RotationalStudy r = run_rotational_study(in, so);
  // r.warnings are the correction's, then the differences': each said where it belongs.
  if (r.correction) {
    warn_all(r.correction->warnings);
    info(g, r.correction_note);
  }
  std::vector<std::string> comments{r.method, "inputs:" + sources, with_flags(r.reciprocity), r.correction_note};
  if (!tip_coherence.empty()) {
    if (tip_coherence.size() != r.block.size())
      throw InputError(fmt::format("the tip FRF's coherence has {} values for the block's {} frequencies", tip_coherence.size(),
                                   r.block.size()),
                       "give the coherence on the tip FRF's frequency lines");
    comments.push_back("coherence: of H00, the tip point FRF (the block's H); identify --averages N uses it");
  }
  write_frf_csv(o.output, r.block, comments, tip_coherence);
  warn_all(r.differences.warnings);
  if (r.differences.reciprocity_mismatch)
    info(g, fmt::format("reciprocity check: max |L - N| / max(|L|, |N|) = {:.3g}", *r.differences.reciprocity_mismatch));
  info(g, fmt::format("wrote {} ({} frequencies)", o.output, r.block.size()));
  if (!o.plot.empty()) draw_figures(g, {{rotational_figure(r), o.plot}}, {o.output});
}

}  // namespace

void add_rotational_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<RotationalCliOptions>();
  CLI::App* c = app.add_subcommand(
      "rotational", "Tip block [[H, L], [N, P]] from translational FRFs by finite differences (Duarte & Ewins 2000)");
  c->add_option("--uff", o->uff,
                "One UFF file holding the whole test: H_ij = the dataset whose response node is point i's and whose "
                "reference node is point j's (--nodes; by default nodes 1, 2, 3: what `toolpoint taptest` writes)");
  c->add_option("--nodes", o->nodes,
                "With --uff: the node numbers of the points, tip first, then s and 2s inwards, comma-separated "
                "(default: 1,2,3), e.g. --nodes 101,102,103")
      ->delimiter(',');
  c->add_option("--direction", o->direction,
                "With --uff: use only datasets whose response and reference direction is this (+X, Y, -Z, code -6..6; "
                "default: any, and two datasets for one pair of points are an error); write a minus as --direction=-Y");
  const auto& fields = rotational_fields();
  o->fields.add(c, option_field(fields, "assume_reciprocity"));
  add_frf_read_options(c, g);
  const FieldSpec& spacing = option_field(fields, "spacing").spec;  // by hand: its short name -s
  c->add_option("-s," + field_flag(spacing), o->fd.spacing, field_help(spacing) + " (required)")
      ->required()
      ->check(plausible_value(plausible::kPointSpacing, "--spacing"));
  o->fields.add(c, option_field(fields, "order"));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const std::string where_i = i == 0 ? "the tip" : fmt::format("{}s inward", i == 1 ? "" : "2");
      const std::string where_j = j == 0 ? "the tip" : fmt::format("{}s inward", j == 1 ? "" : "2");
      c->add_option(fmt::format("--h{}{}", i, j), o->files[i][j],
                    fmt::format("H{}{} [m/N], response at {}, force at {}: a single FRF file, formats below{}", i, j, where_i,
                                where_j, i == 0 && j == 0 ? " (required unless --uff)" : " (default: none)"));
    }
  o->fields.add(c, option_field(fields, "symmetrise"));
  c->add_option("--shear-stiffness", o->shear_stiffness,
                "κGA [N] of the section under the points: removes the shear strain from N, L (1/κGA) and P (c/(s κGA)), "
                "giving the section rotation the coupling equations use; default: none (total slope dw/dx)")
      ->check(plausible_value(plausible::kShearStiffness, "--shear-stiffness"));
  c->add_option("--p-method", o->p_method,
                "P from: auto (cross terms if all H_ij are given, else N*L/H00), cross (cross terms, error if "
                "missing), n2h (always N*L/H00, Schmitz & Smith)")
      ->check(CLI::IsMember({"auto", "cross", "n2h"}))
      ->capture_default_str();
  c->add_option("-o,--output", o->output,
                "Output 2×2 block FRF CSV, the one format that carries rotations (H m/N, L 1/N, N rad/N, P rad/(N m)) "
                "(required)")
      ->required();
  c->add_option("--model", o->model,
                "Assembly file (TOML) of the structure tested: the same differences applied to the model's FRFs at the same "
                "points, against the model's exact tip block, estimate the truncation error of L, N and P, which is then "
                "removed (to first order in the model's error); needs --at. Default: no correction")
      ->option_text("A.toml");
  c->add_option("--at", o->at_site,
                "With --model: where the points are: tool (on the tool of the whole assembly, for SHT11) or holder (on the "
                "holder with the tool removed, for SH11)")
      ->check(CLI::IsMember({"tool", "holder"}));
  add_plot_option(c, o->plot,
                  "the block: |H| [m/N], |L| and |N| [1/N], |P| [rad/(N·m)] and the four phases [deg] against frequency [Hz]");
  c->footer(std::string(kFigureFooter) +
            "Points: 0 at the tool tip, 1 and 2 at s and 2s towards the spindle; H_ij = w_i/f_j. N needs\n"
            "H10 (and H20), L needs H01 (and H02); a missing one is an error unless --assume-reciprocity\n"
            "takes it from H_ji (with the hammer at the tip only, that makes L = N). P needs H11 (and H12,\n"
            "H21, H22) too; otherwise P ~ N*L/H00, which is about 25 % low on a static cantilever (a warning\n"
            "says so). All inputs share one grid (`toolpoint resample` puts them on one).\n"
            "Input formats: " +
            std::string(kSingleFrfHelp) +
            ".\n"
            "Example:\n"
            "  toolpoint rotational --uff tap_tool.uff --spacing 0.01 --order 2 --output sht11.csv\n"
            "  toolpoint rotational --uff testlab.uff --nodes 101,102,103 --direction +Y --spacing 0.02 --output sht11.csv\n"
            "  toolpoint rotational --spacing 0.04 --order 2 --h00 tip.csv --h10 p1.csv --h20 p2.csv \\\n"
            "      --h11 p1p1.csv --h21 p2p1.csv --h22 p2p2.csv --output SHT11.csv --plot SHT11.png\n"
            "  (with every FRF in one universal file: --h00 tap.uff#0 --h10 tap.uff#1 …)\n"
            "  toolpoint rotational --uff tap_holder.uff --spacing 0.02 --model A.toml --at holder --output sh11.csv\n"
            "      (the truncation error of the differences, estimated on the model A.toml, removed)");
  c->callback([o, &g] { run_rotational(*o, g); });
}

}  // namespace toolpoint::cli
