// toolpoint resample: an FRF (or 2×2 block) cropped to a band, or interpolated onto another file's
// frequencies or a given grid, so that measurements can be combined. Units: frequencies in Hz,
// values in the file's units (receptance m/N after reading). --plot overlays input and result.
#include <fmt/format.h>
#include <memory>

#include "cli.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/measured/resample.hpp"
#include "toolpoint/studies/resample.hpp"

namespace toolpoint::cli {

namespace {

struct ResampleOptions {
  std::string input, output, band, onto, grid, method = "linear", plot;
  std::optional<std::size_t> dataset;
};

void run_resample(const ResampleOptions& o, const Globals& g) {
  check_plot_path(o.plot);
  const FrfFormat format = output_frf_format(o.output);
  check_paths({{o.input, "input"}, {o.onto, "--onto"}}, {{o.output, "output"}, {o.plot, "--plot"}});
  if (o.band.empty() && o.onto.empty() && o.grid.empty())
    throw InvalidArgument("resample needs a band to crop to (--band) or frequencies to interpolate onto (--onto, --grid)",
                          "e.g. --band 500:3000, --onto other.csv or --grid 500:3000:2.5");
  if (!o.onto.empty() && !o.grid.empty()) throw InvalidArgument("give either --onto FILE or --grid START:STOP:STEP, not both");
  FrfResampleOptions ro;
  ro.method = parse_interpolation(o.method, "--method");
  if (!o.band.empty()) ro.band_hz = parse_range(o.band, "--band");
  // The target grid, before any work on the input.
  if (!o.onto.empty()) {
    Globals plain = g;
    plain.frf = {};  // the reading options are for the input; the grid file is read as it is
    const FrfFileData t = read_frf_input(plain, o.onto);
    ro.target_hz = t.is_block ? t.block.frequency_hz : t.single.frequency_hz;
    ro.target_name = "the frequencies of " + o.onto;
  } else if (!o.grid.empty()) {
    ro.target_hz = parse_frequency_grid(o.grid, "--grid").values();
    ro.target_name = "--grid " + o.grid;
  }
  ro.check();

  const FrfFileData in = read_frf_input(g, o.input, o.dataset);
  check_frf_output(o.output, format, in.is_block);
  FrfResampled r = run_resample_study(in, ro, o.input);
  FrfFileData& out = r.data;
  out.format = format;
  const std::string comment = fmt::format("{} {}", o.input, r.description);
  write_frf_output(o.output, format, out, comment);
  warn_all(r.warnings);
  const std::vector<double>& f_in = in.is_block ? in.block.frequency_hz : in.single.frequency_hz;
  const std::vector<double>& f_out = out.is_block ? out.block.frequency_hz : out.single.frequency_hz;
  info(g, fmt::format("wrote {} ({} frequencies {:.6g}–{:.6g} Hz from {} of {:.6g}–{:.6g} Hz: {})", o.output, f_out.size(),
                      f_out.front(), f_out.back(), f_in.size(), f_in.front(), f_in.back(), r.description));
  if (o.plot.empty()) return;
  plot::FrfFigureOptions fo;
  fo.title = fmt::format("{}: {}", plot::literal(o.input), r.description);
  draw_frf_overlay(g, {{point_frf(in), "input", plot::CurveStyle::Points}, {point_frf(out), "resampled", plot::CurveStyle::Line}},
                   fo, o.plot, o.output);
}

}  // namespace

void add_resample_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<ResampleOptions>();
  CLI::App* c = app.add_subcommand(
      "resample",
      "An FRF on another frequency grid: cropped to a band, or interpolated onto another file's frequencies or a "
      "given grid (only inside the measured range)");
  c->add_option("input", o->input, std::string("Input FRF (required): ") + kSingleFrfHelp + ", or a 2×2 block CSV")->required();
  c->add_option("output", o->output,
                "Output file (required), same form as the input, format by extension: .csv, .uff/.unv/.uf or .frf; .csv "
                "for a block")
      ->required();
  c->add_option("--band", o->band, "Keep F1 ≤ f ≤ F2 only, as F1:F2 [Hz] (crops the input, or the target grid)");
  c->add_option("--onto", o->onto, "Interpolate onto the frequencies of this FRF file (any format; FILE#N for a UFF dataset)");
  c->add_option("--grid", o->grid, "Interpolate onto START:STOP:STEP [Hz]");
  c->add_option("--method", o->method,
                "Interpolation of real and imaginary parts: linear (second order, no overshoot) or cubic (natural "
                "cubic spline, fourth order in the interior)")
      ->capture_default_str();
  add_dataset_option(c, o->dataset);
  add_frf_read_options(c, g);
  add_plot_option(c, o->plot, "the input (points) and the result (line), |H| [m/N] and phase [deg] against frequency [Hz]");
  c->footer(std::string(kFigureFooter) +
            "Interpolation never extrapolates: a target frequency outside the input's measured range is an error\n"
            "(crop the target with --band). Measured frequencies keep their values exactly; a coherence column\n"
            "is interpolated linearly.\n"
            "Examples:\n"
            "  toolpoint resample sh11.csv sh11_band.csv --band 500:4000\n"
            "  toolpoint resample session2.uff session2_on1.csv --onto session1.csv --method cubic\n"
            "  toolpoint resample tip.frf tip_1hz.csv --grid 100:5000:1");
  c->callback([o, &g] { run_resample(*o, g); });
}

}  // namespace toolpoint::cli
