// The field figures drawn by tools/plot/plot_figures.py from a tiny fields CSV (each particle its
// filled domain, the pile over them), and the bodies' VTU read back by Python's XML parser.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "../support/files.hpp"
#include "pilempm/io/centrifuge_case.hpp"
#include "pilempm/io/mpm_output.hpp"
#include "pilempm/io/output/atomic_file.hpp"
#include "pilempm/io/vtu_writer.hpp"
#include "pilempm/mpm/rigid_body.hpp"
#include "pilempm/study/centrifuge_run.hpp"
#include "pilempm/study/figures.hpp"
#include "pilempm/study/plotting.hpp"

namespace pilempm {
namespace {

namespace fs = std::filesystem;
using test_support::read_text;

// The Python with matplotlib that draw_figures finds ("" when none).
std::string python_with_matplotlib(const fs::path& script) {
  for (const char* python : {"/usr/bin/python3", "python3"}) {
    const ProcessResult r = run_process(python, {script.string(), "--check"});
    if (r.started && r.exit_code == 0) return python;
  }
  return "";
}

TEST(FieldFigures, EachParticleIsAFilledRectangleWithThePileDrawnOver) {
  const fs::path dir = test_support::fresh_test_path("field-figure");
  fs::create_directories(dir);
  const scenario::CentrifugeScenario s =
      read_centrifuge_case_text(quick_centrifuge_case_text(), "quick.toml");
  const double D = 1e3 * s.pile_diameter, tip = D * (s.wished_in_place_D + s.installation_D);
  // Particles filling the figure's zone (r <= 5 D, 3 D above to 5 D below the tip), 0.25 D
  // apart, with a void ratio growing with r; the pile's half-section with a 60° cone.
  std::string fields =
      "# tiny\nr_mm,depth_mm,void_ratio,p_kPa,q_kPa,igs_rho,half_r_mm,"
      "half_depth_mm\n";
  const double h = 0.25 * D;
  for (double r = 0.5 * h; r < 5.0 * D; r += h)
    for (double z = tip - 3.0 * D + 0.5 * h; z < tip + 5.0 * D; z += h)
      fields += fmt::format("{},{},{},{},{},{},{},{}\n", r, z, 0.6 + 0.3 * r / (5.0 * D), 10.0 + z,
                            5.0 + r, r / (5.0 * D), 0.5 * h, 0.5 * h);
  write_file_atomically(dir / "fields_installation.csv", fields);
  const double cone = 0.5 * D / std::tan(std::numbers::pi / 6.0);
  write_file_atomically(dir / "fields_installation_pile.csv",
                        fmt::format("r_mm,depth_mm\n0,{}\n{},{}\n{},{}\n0,{}\n", tip, 0.5 * D,
                                    tip - cone, 0.5 * D, -10.0 * D, -10.0 * D));
  const FigureSpec figure = centrifuge_field_figure(s, "installation", "fields_installation.csv",
                                                    "fields_installation.png");
  const std::string json = figures_json({figure});
  EXPECT_NE(json.find("\"half_x\": \"half_r_mm\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"csv\": \"fields_installation_pile.csv\""), std::string::npos);
  EXPECT_NE(json.find("\"fill\""), std::string::npos);
  write_file_atomically(dir / "figures.json", json);
  write_file_atomically(dir / "plot_figures.py", std::string(plot_script_text()));
  const std::string python = python_with_matplotlib(dir / "plot_figures.py");
  if (python.empty()) GTEST_SKIP() << "no Python with matplotlib here; CI installs it";

  const PlotOutcome drawn = draw_figures(dir / "plot_figures.py", dir / "figures.json", python);
  ASSERT_TRUE(drawn.plotted) << drawn.problem;
  const std::string png = read_text(dir / "fields_installation.png");
  ASSERT_GT(png.size(), 10000u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // Filled fields cover their panels: the share of coloured pixels (neither white, grey nor
  // black) in the figure; dots 0.25 D apart would leave most of each panel white. The pile is
  // drawn over the fields: its grey (0.6) shows.
  const ProcessResult shares = run_process(
      python, {"-c",
               "import sys, matplotlib.image as m\n"
               "a = m.imread(sys.argv[1])[:, :, :3]\n"
               "spread = a.max(axis=2) - a.min(axis=2)\n"
               "print((spread > 0.08).mean(), (abs(a - 0.6).max(axis=2) < 0.02).mean())\n",
               (dir / "fields_installation.png").string()});
  ASSERT_EQ(shares.exit_code, 0) << shares.output;
  std::istringstream values(shares.output);
  double coloured = 0.0, grey = 0.0;
  values >> coloured >> grey;
  EXPECT_GT(coloured, 0.25) << shares.output;
  EXPECT_GT(grey, 0.002) << shares.output;
  fs::remove_all(dir);
}

TEST(FieldFigures, TheBodiesVtuIsWellFormedXmlWithTheBodysVertices) {
  const fs::path dir = test_support::fresh_test_path("bodies-vtu");
  fs::create_directories(dir);
  mpm::RigidBody pile = mpm::RigidBody::pile(0.005, 0.3, std::numbers::pi / 3.0, 10.0);
  pile.translate(mpm::Vec2(0.0, -0.02));
  const std::vector<mpm::Vec2> outline = mpm_body_outline(pile, 0.5);
  PolygonMesh mesh;
  for (const mpm::Vec2& v : outline) {
    mesh.connectivity.push_back(static_cast<std::int64_t>(mesh.coordinates.size() / 3));
    mesh.coordinates.insert(mesh.coordinates.end(), {v.x(), v.y(), 0.0});
  }
  mesh.offsets.push_back(static_cast<std::int64_t>(mesh.connectivity.size()));
  write_vtu(dir / "bodies_00000.vtu", mesh);
  PvdSeries series(dir / "particles.pvd");
  series.add(0.5, dir / "bodies_00000.vtu", 1);
  series.write();
  const ProcessResult r = run_process(
      "python3", {"-c",
                  "import sys, base64, struct, xml.etree.ElementTree as E\n"
                  "E.parse(sys.argv[2])\n"
                  "piece = E.parse(sys.argv[1]).getroot().find('UnstructuredGrid/Piece')\n"
                  "raw = base64.b64decode(piece.find('Points/DataArray').text.strip())\n"
                  "n = struct.unpack('<Q', raw[:8])[0] // 8\n"
                  "print(' '.join(repr(v) for v in struct.unpack('<%dd' % n, raw[8:])))\n",
                  (dir / "bodies_00000.vtu").string(), (dir / "particles.pvd").string()});
  if (!r.started) GTEST_SKIP() << "no python3 here";
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream values(r.output);
  std::vector<double> read;
  for (double v; values >> v;) read.push_back(v);
  EXPECT_EQ(read, mesh.coordinates);
  // The cone's apex where the pile went.
  double lowest = read.at(1);
  for (std::size_t k = 1; k < read.size(); k += 3) lowest = std::min(lowest, read[k]);
  EXPECT_DOUBLE_EQ(lowest, 0.28);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pilempm
