// toolpoint convert: measured FRF files between formats (FRF CSV, UFF dataset 58/58b, CutPro
// .frf), and a listing of the datasets 58 in a universal file. Units: receptance m/N against
// frequency Hz (UFF mobility/accelerance converted on request). --plot draws what was written, as
// receptance: |H| [m/N] and phase [deg] against frequency [Hz].
#include <fmt/format.h>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/plot/plot.hpp"
#include "toolpoint/io/uff.hpp"

namespace toolpoint::cli {

namespace {

struct ConvertOptions {
  std::string input, output, from = "auto", to = "auto", plot;
  std::optional<std::size_t> dataset;
  std::optional<int> response_node, reference_node;
  std::string response_dir, reference_dir;
  bool list = false, json = false;
};

UffSelection selection_of(const ConvertOptions& o) {
  UffSelection s;
  s.index = o.dataset;
  s.response_node = o.response_node;
  s.reference_node = o.reference_node;
  if (!o.response_dir.empty()) s.response_direction = parse_uff_direction(o.response_dir, "--response-dir");
  if (!o.reference_dir.empty()) s.reference_direction = parse_uff_direction(o.reference_dir, "--reference-dir");
  return s;
}

std::string other_types(const UffFile& f) {
  std::map<int, std::size_t> count;
  for (const auto& d : f.datasets)
    if (d.type != 58) ++count[d.type];
  std::string s;
  for (const auto& [type, n] : count) s += fmt::format("{}{} ×{}", s.empty() ? "" : ", ", type, n);
  return s;
}

// The listing reads headers only: the point count is record 7's (warnings say when the data hold
// fewer).
std::string points_text(const UffDataset58& d) {
  if (d.headers_only) return fmt::format("{}", d.declared_points);
  return static_cast<long long>(d.size()) == d.declared_points ? fmt::format("{}", d.size())
                                                               : fmt::format("{} of {}", d.size(), d.declared_points);
}

// Messages for a person: the first `shown` of `items`, then how many more.
void print_capped(const std::vector<std::string>& items, std::size_t shown, const std::string& prefix, const std::string& more,
                  bool as_warnings) {
  for (std::size_t i = 0; i < items.size() && i < shown; ++i) {
    if (as_warnings) warn(items[i]);
    else std::cout << prefix << items[i] << '\n';
  }
  if (items.size() > shown) {
    const std::string line = fmt::format("… and {} more {} (all of them: --list --json)", items.size() - shown, more);
    if (as_warnings) warn(line);
    else std::cout << prefix << line << '\n';
  }
}

std::string ordinate_text(const UffDataset58& d) {
  std::string s = uff_data_type_name(d.ordinate.data_type);
  if (d.denominator.data_type != 0) s += "/" + uff_data_type_name(d.denominator.data_type);
  if (const auto k = uff_ordinate_kind(d); k && d.denominator.data_type == 13) s = frf_ordinate_name(*k);
  return s;
}

void run_list(const ConvertOptions& o) {
  const FrfFormat format = o.from == "auto" ? frf_format_of_path(o.input) : parse_frf_format(o.from, "--from");
  if (format != FrfFormat::Uff)
    throw InvalidArgument(fmt::format("--list lists the datasets of a UFF file; {} is {}", o.input, frf_format_name(format)),
                          "give a .uff/.unv/.uf file or --from uff");
  const UffFile f = read_uff(o.input, {.headers_only = true});
  if (o.json) {
    nlohmann::json out = f;
    out["units"] = "abscissa in the file's own units (see abscissa.units); frequency in Hz for FRFs";
    std::cout << out.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format("{}: {} dataset(s) 58, {} of other types{}\n", f.source, f.functions.size(),
                           f.datasets.size() - f.functions.size() - f.skipped.size(),
                           other_types(f).empty() ? "" : " (" + other_types(f) + ")");
  if (!f.functions.empty())
    std::cout << fmt::format("{:>5}  {:<32} {:<12} {:<12} {:>17}  {:<15} {:<28} {:<34} {}\n", "index", "function (type)",
                             "response", "reference", "points", "values", "ordinate", "abscissa first..last [units]",
                             "ID line 1");
  for (const auto& d : f.functions) {
    const std::string range = d.declared_points == 0
                                  ? std::string("-")
                                  : fmt::format("{:.6g}..{:.6g} [{}]", d.abscissa_first, d.abscissa_last, d.abscissa.units);
    std::cout << fmt::format("{:>5}  {:<32} {:<12} {:<12} {:>17}  {:<15} {:<28} {:<34} {}\n", d.index,
                             fmt::format("{} ({})", uff_function_type_name(d.function_type), d.function_type),
                             fmt::format("{} {}", d.response_node, uff_direction_name(d.response_direction)),
                             fmt::format("{} {}", d.reference_node, uff_direction_name(d.reference_direction)), points_text(d),
                             uff_ordinate_type_name(d.ordinate_data_type), ordinate_text(d), range, d.id[0]);
  }
  print_capped(f.skipped, 10, "skipped: ", "datasets 58 skipped", false);
  std::vector<std::string> problems = f.file_warnings;  // linear: no search of one list in another
  for (const auto& d : f.functions) problems.insert(problems.end(), d.warnings.begin(), d.warnings.end());
  print_capped(problems, 20, "", "warnings", true);
}

// The datasets 58 a UFF-to-UFF copy wrote, each as receptance, overlaid. Datasets that are no FRF
// (or of an unknown ordinate) are left out with a warning.
plot::Figure copied_datasets_figure(const ConvertOptions& o, const std::vector<UffDataset58>& sets) {
  std::vector<plot::FrfTrace> traces;
  for (const UffDataset58& d : sets) {
    try {
      UffReceptance r = uff_receptance(d, std::nullopt, o.input);
      traces.push_back(
          {std::move(r.receptance),
           fmt::format("dataset {}: {} {} / {} {}", d.index, d.response_node, uff_direction_name(d.response_direction),
                       d.reference_node, uff_direction_name(d.reference_direction)),
           plot::CurveStyle::Line});
    } catch (const InputError& e) {
      warn(fmt::format("not drawn: {}", e.what()));
    }
  }
  if (traces.empty())
    throw InputError(fmt::format("{}: no dataset written is an FRF that can be drawn as receptance", o.output),
                     "pick an FRF dataset with --dataset (see --list), or drop --plot");
  plot::FrfFigureOptions fo;
  fo.title = fmt::format("{} → {}", plot::literal(o.input), plot::literal(o.output));
  fo.mode_labels = traces.size() == 1 ? 6 : 0;
  return plot::frf_figure(traces, fo);
}

void run_convert(const ConvertOptions& o, const Globals& g) {
  FrfReadOptions r = frf_read_options(g.frf);
  check_plot_path(o.plot);
  if (o.list) {
    if (!o.output.empty() || !o.plot.empty())
      throw InvalidArgument("--list takes only the input file", "drop OUT and --plot, or drop --list");
    run_list(o);
    return;
  }
  if (o.json) throw InvalidArgument("--json goes with --list", "add --list, or drop --json");
  if (o.output.empty()) throw InvalidArgument("convert needs IN and OUT (or --list)", "e.g. toolpoint convert tap.uff tap.csv");
  const FrfFormat in = o.from == "auto" ? frf_format_of_path(o.input) : parse_frf_format(o.from, "--from");
  const FrfFormat out = o.to == "auto" ? frf_format_of_path(o.output) : parse_frf_format(o.to, "--to");
  if (in == FrfFormat::UffBinary)
    throw InvalidArgument("--from uffb is not needed: --from uff reads ASCII 58 and binary 58b", "use --from uff");
  const UffSelection sel = selection_of(o);
  check_paths({{o.input, "input"}}, {{o.output, "output"}, {o.plot, "--plot"}});

  // UFF to UFF: the datasets 58 themselves (all, or the selected one), every field kept.
  if (in == FrfFormat::Uff && (out == FrfFormat::Uff || out == FrfFormat::UffBinary) && !r.ordinate && !r.units) {
    const UffFile f = read_uff(o.input);
    std::vector<const UffDataset58*> chosen;
    if (sel.empty() && !f.functions.empty())
      for (const auto& d : f.functions) chosen.push_back(&d);
    else chosen.push_back(&select_dataset58(f, sel));
    warn_all(f.warnings_for(chosen));
    std::vector<UffDataset58> sets;
    for (const UffDataset58* d : chosen) sets.push_back(*d);
    if (const std::string others = other_types(f); !others.empty())
      warn(fmt::format("{}: datasets of other types not written ({}): only datasets 58 are converted", o.input, others));
    UffWriteOptions w;
    w.binary = out == FrfFormat::UffBinary;
    try {
      warn_all(write_uff(o.output, sets, w));
    } catch (const InvalidArgument& e) {  // what was read does not fit the format: the input's fault
      throw InputError(fmt::format("{}: a dataset read from it cannot be written as UFF: {}", o.input, e.what()),
                       "convert the one FRF you need to CSV instead (--dataset N)");
    }
    info(g, fmt::format("wrote {} ({} dataset(s) 58 as {})", o.output, sets.size(), w.binary ? "binary 58b" : "ASCII 58"));
    if (!o.plot.empty()) draw_figures(g, {{copied_datasets_figure(o, sets), o.plot}}, {o.output});
    return;
  }

  r.format = in;
  FrfWriteOptions w;
  w.format = out;
  if (in == FrfFormat::Uff) {
    r.uff = sel;
  } else if (!sel.empty()) {
    // Not a UFF input: the node/direction options label the written dataset instead.
    if (sel.index)
      throw InvalidArgument("--dataset selects a dataset of a UFF input file; " + o.input + " is not UFF",
                            "drop --dataset for CSV and .frf inputs");
    if (out != FrfFormat::Uff && out != FrfFormat::UffBinary)
      throw InvalidArgument(
          "--response-node/--reference-node/--*-dir apply to a UFF input (selection) or a UFF output "
          "(labels); here neither is UFF",
          "drop them, or write a .uff file to label its dataset");
  }
  const FrfFileData data = read_frf_file_for_cli(o.input, r);
  w.dof = data.dof;
  w.coherence = data.coherence;
  if (in != FrfFormat::Uff) {
    w.dof.response_node = sel.response_node.value_or(0);
    w.dof.response_direction = sel.response_direction.value_or(0);
    w.dof.reference_node = sel.reference_node.value_or(0);
    w.dof.reference_direction = sel.reference_direction.value_or(0);
  }
  w.description = in == FrfFormat::Uff ? "from " + data.description : std::string();
  warn_all(data.warnings);
  const std::string title = fmt::format("{} → {}", plot::literal(o.input), plot::literal(o.output));
  if (data.is_block) {
    warn_all(write_frf_file(o.output, data.block, w));
    info(g, fmt::format("wrote {} ({} frequencies, 2×2 receptance blocks)", o.output, data.block.size()));
    if (!o.plot.empty()) draw_figures(g, {{plot::block_figure(data.block, title), o.plot}}, {o.output});
    return;
  }
  warn_all(write_frf_file(o.output, data.single, w));
  info(g, fmt::format("wrote {} ({} frequencies {:.6g}..{:.6g} Hz, receptance m/N{})", o.output, data.single.size(),
                      data.single.frequency_hz.front(), data.single.frequency_hz.back(),
                      data.ordinate == FrfOrdinate::Receptance && data.units.to_si == 1.0
                          ? std::string()
                          : fmt::format(", converted from {} in {}", frf_ordinate_name(data.ordinate), data.units.label)));
  if (o.plot.empty()) return;
  plot::FrfFigureOptions fo;
  fo.title = title;
  fo.mode_labels = 6;
  draw_frf_overlay(g, {{data.single, "receptance", plot::CurveStyle::Line}}, fo, o.plot, o.output);
}

}  // namespace

void add_convert_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* c =
      app.add_subcommand("convert",
                         "Measured FRF files between formats: FRF CSV, UFF dataset 58 (ASCII) / 58b (binary), CutPro .frf; "
                         "UFF datasets listed with --list");
  c->add_option("IN", o->input,
                "Input file (required): .csv (FRF CSV, single or 2×2 block), .uff/.unv/.uf (UFF 58 or 58b), .frf "
                "(CutPro text)")
      ->required();
  c->add_option("OUT", o->output,
                "Output file, format by extension (.csv, .uff/.unv/.uf ASCII UFF, .frf) or --to; "
                "receptance [m/N] against frequency [Hz]; a 2×2 block: .csv only (required unless --list)");
  c->add_option("--from", o->from, "Input format: auto (by extension), csv, uff or frf")->capture_default_str();
  c->add_option("--to", o->to, "Output format: auto (by extension), csv, uff (ASCII 58), uffb (binary 58b) or frf")
      ->capture_default_str();
  auto* ds = c->add_option("--dataset", o->dataset,
                           "UFF input: the dataset 58 to read, by index from 0 as --list shows (default: the only one)");
  auto* rn = c->add_option("--response-node", o->response_node,
                           "UFF input: select by response node; UFF output from CSV/.frf: label (default: any / 0)");
  auto* rd =
      c->add_option("--response-dir", o->response_dir,
                    "Response direction: +X, Y-, Z, +RZ, scalar or a code -6..6 (selection or label as above; default: any / 0, "
                    "scalar); write a leading minus as --response-dir=-Y");
  auto* fn = c->add_option("--reference-node", o->reference_node,
                           "Reference (excitation) node (selection or label as above; default: any / 0)");
  auto* fd = c->add_option("--reference-dir", o->reference_dir,
                           "Reference direction, as --response-dir (default: any / 0, scalar)");
  for (auto* opt : {rn, rd, fn, fd}) ds->excludes(opt);
  add_frf_read_options(c, g);
  c->add_flag("--list", o->list,
              "List the datasets 58 of a UFF input: index, function type, nodes/directions, points (as record 7 "
              "declares them), value type, ordinate, abscissa range, ID line. Reads the headers only: a 1 GB file "
              "lists in seconds");
  c->add_flag("--json", o->json, "With --list: machine-readable output on stdout");
  add_plot_option(c, o->plot,
                  "the FRF written, as receptance: |H| [m/N] and phase [deg] against frequency [Hz], modes labelled "
                  "(a block: all four entries; UFF to UFF: every dataset copied, overlaid)");
  c->footer(std::string(kFigureFooter) +
            "Points at 0 Hz are dropped (with a warning). UFF to UFF copies the datasets 58 unchanged (all of them, or\n"
            "the selected one); with --ordinate or --units the selected FRF is converted to receptance instead.\n"
            "Examples:\n"
            "  toolpoint convert tap_test.uff --list\n"
            "  toolpoint convert tap_test.uff tool_tip.csv --response-node 1 --response-dir +X --ordinate accelerance\n"
            "  toolpoint convert tool_tip.csv tool_tip.frf --plot tool_tip.png\n"
            "  toolpoint convert export.csv tool_tip.csv --format mag-phase-deg --units g/N    # what the header cannot say");
  c->callback([o, &g] { run_convert(*o, g); });
}

}  // namespace toolpoint::cli
