// toolpoint couple: the semi-analytical tool point FRF — a measured SH11 + the model's tool + the
// holder–tool joint (seed Eq. 5), for one tool overhang or a sweep (the seed's Fig. 10).
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "toolpoint/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/peaks.hpp"

namespace toolpoint::cli {

namespace {

struct CoupleOptions {
  std::string sh, assembly, overhang, output;
  bool json = false;
};

void run_couple(const CoupleOptions& o, const Globals& g) {
  LoadedAssembly loaded = load_assembly(o.assembly);
  warn_all(loaded.warnings);
  const BlockSeries sh = read_block_csv(o.sh);
  validate(sh, o.sh, 3);
  std::vector<double> overhangs;
  bool sweep = false;
  if (o.overhang.empty()) {
    overhangs.push_back(loaded.assembly.tool.overhang);
  } else if (o.overhang.find(':') != std::string::npos) {
    // A sweep START:STOP:STEP in m; reuse the grid parser's checks with its own wording.
    const FrequencyGrid gsw = [&] {
      try {
        return parse_frequency_grid(o.overhang, "--overhang");
      } catch (const InvalidArgument& e) {
        throw InvalidArgument(std::string(e.what()) + " (here in metres, not Hz)", "e.g. --overhang 0.040:0.060:0.002");
      }
    }();
    overhangs = gsw.values();
    sweep = true;
  } else {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(o.overhang, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != o.overhang.size()) throw InvalidArgument(fmt::format("--overhang '{}' is not a length in m or START:STOP:STEP", o.overhang));
    overhangs.push_back(v);
  }
  if (overhangs.size() > 1000) throw InvalidArgument(fmt::format("--overhang gives {} overhangs; at most 1000", overhangs.size()));
  if (sweep && o.output.empty()) throw InvalidArgument("an overhang sweep needs --output DIR");

  const double inside = loaded.assembly.tool.length - loaded.assembly.tool.overhang;
  Table table;
  std::size_t max_modes = 0;
  std::vector<std::vector<Peak>> all_peaks;
  nlohmann::json j;
  j["sh11"] = o.sh;
  j["assembly"] = o.assembly;
  j["tool_inside_holder_m"] = inside;
  j["overhangs"] = nlohmann::json::array();
  for (double L : overhangs) {
    const Assembly a = with_overhang(loaded.assembly, L);
    const BlockSeries sht = couple_tool(a, sh, o.sh);
    const auto peaks = find_peaks(entry(sht, 0));
    max_modes = std::max(max_modes, peaks.size());
    all_peaks.push_back(peaks);
    std::string file;
    if (!o.output.empty()) {
      file = sweep ? fmt::format("{}/sht11_overhang_{:.1f}mm.csv", o.output, 1000 * L) : o.output;
      write_frf_csv(file, sht,
                    {fmt::format("tool point SHT11: measured SH11 ({}) + model tool, overhang {} m (tool length {} m), Eq. (5)", o.sh, L,
                                 inside + L)});
    }
    nlohmann::json modes = nlohmann::json::array();
    for (const Peak& p : peaks) modes.push_back({{"peak_frequency_hz", p.frequency_hz}, {"peak_magnitude_m_per_n", p.magnitude}});
    j["overhangs"].push_back({{"overhang_m", L}, {"file", file}, {"modes", modes}});
  }
  table.columns = {"overhang_m"};
  for (std::size_t m = 0; m < max_modes; ++m) table.columns.push_back(fmt::format("mode_{}_hz", m + 1));
  for (std::size_t i = 0; i < overhangs.size(); ++i) {
    std::vector<double> row{overhangs[i]};
    for (std::size_t m = 0; m < max_modes; ++m)
      row.push_back(m < all_peaks[i].size() ? all_peaks[i][m].frequency_hz : std::numeric_limits<double>::quiet_NaN());
    table.rows.push_back(row);
  }
  if (sweep) {
    write_table_csv(o.output + "/natural_frequencies.csv", table,
                    {"peaks of |H| of the coupled tool point FRF against tool overhang (seed Fig. 10); nan: no peak",
                     "overhang in m, frequencies in Hz"});
    j["natural_frequencies_file"] = o.output + "/natural_frequencies.csv";
  }
  if (o.json) {
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format("tool point FRF from {} + model tool ({:.1f} mm inside the holder) + holder–tool joint (Eq. 5)\n", o.sh,
                           1000 * inside);
  std::cout << "overhang_mm  peak frequencies of |H| [Hz]\n";
  for (std::size_t i = 0; i < overhangs.size(); ++i) {
    std::cout << fmt::format("{:11.1f} ", 1000 * overhangs[i]);
    for (const Peak& p : all_peaks[i]) std::cout << fmt::format(" {:9.1f}", p.frequency_hz);
    std::cout << "\n";
  }
  if (!o.output.empty()) info(g, sweep ? fmt::format("wrote {} FRFs and natural_frequencies.csv to {}/", overhangs.size(), o.output)
                                       : fmt::format("wrote {}", o.output));
}

}  // namespace

void add_couple_command(CLI::App& app, Globals& g) {
  auto o = std::make_shared<CoupleOptions>();
  CLI::App* c = app.add_subcommand("couple", "Tool point FRF from a measured SH11 and the model's tool, for any overhang (seed Eq. 5, Fig. 10)");
  c->add_option("--sh", o->sh, "SH11 block CSV at the holder tip (measured, e.g. via `toolpoint rotational`)")->required()->check(CLI::ExistingFile);
  c->add_option("--assembly", o->assembly, "Assembly file (TOML): the tool and the holder–tool joint")->required()->check(CLI::ExistingFile);
  c->add_option("--overhang", o->overhang,
                "Tool overhang [m], or a sweep START:STOP:STEP [m]; default: the file's. The length inside the holder is kept");
  c->add_option("--output", o->output, "One overhang: the SHT11 block CSV; a sweep: a folder for one CSV per overhang and natural_frequencies.csv");
  c->add_flag("--json", o->json, "Machine-readable output on stdout");
  c->footer(
      "Example:\n"
      "  toolpoint couple --sh sh11.csv --assembly examples/bt40_shrinkfit_16mm.toml \\\n"
      "      --overhang 0.040:0.060:0.002 --output overhangs");
  c->callback([o, &g] { run_couple(*o, g); });
}

}  // namespace toolpoint::cli
