// `pilempm calibrate` end to end on the example, and its parameters.toml used unchanged by an
// element case and a centrifuge case.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "run_pilempm.hpp"

namespace {

namespace fs = std::filesystem;
using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

TEST(CalibrateCli, ExampleFitsAndItsParametersRunInElementAndCentrifugeCases) {
  const fs::path out = fs::temp_directory_path() / "pilempm_calibrate_cli";
  fs::remove_all(out);
  const std::string source = PILEMPM_SOURCE_DIR;
  const Result r =
      run_pilempm("calibrate '" + source +
                  "/examples/calibration/baskarp.toml' --no-plots --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("at most"), std::string::npos) << r.output;  // progress with ETA
  for (const char* file : {"parameters.toml", "report.md", "history.csv", "figures.json",
                           "tx-100-e0.60.data.csv", "tx-100-e0.60.fit.csv"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  const std::string parameters = read_text(out / "parameters.toml");
  EXPECT_NE(read_text(out / "report.md").find("| e_i0 |"), std::string::npos);

  // An element case: the [[material]] of parameters.toml, unchanged, and a test using it.
  std::ofstream(out / "element.toml")
      << "[[test]]\nname = \"tx\"\ntype = \"triaxial\"\nset = \"baskarp-fitted\"\ne0 = 0.6\n"
         "e0_at = \"initial-stress\"\nsigma3_kPa = 100\naxial_strain = 0.05\nsteps = 50\n\n"
      << parameters;
  const Result element = run_pilempm("element run '" + (out / "element.toml").string() +
                                     "' --out '" + (out / "element").string() + "'");
  EXPECT_EQ(element.exit_code, 0) << element.output;

  // A centrifuge case: the quick case with its sand made of the fitted material.
  std::string quick = read_text(fs::path(source) / "examples/centrifuge/quick.toml");
  const std::string original = "material = \"original\"";
  ASSERT_NE(quick.find(original), std::string::npos);
  quick.replace(quick.find(original), original.size(), "material = \"baskarp-fitted\"");
  std::ofstream(out / "centrifuge.toml") << quick << "\n" << parameters;
  const Result centrifuge =
      run_pilempm("centrifuge case '" + (out / "centrifuge.toml").string() + "'");
  EXPECT_EQ(centrifuge.exit_code, 0) << centrifuge.output;
  EXPECT_NE(centrifuge.output.find("baskarp-fitted"), std::string::npos) << centrifuge.output;
  fs::remove_all(out);
}

TEST(CalibrateCli, BadDataStopWithFileLineAndColumn) {
  const fs::path dir = fs::temp_directory_path() / "pilempm_calibrate_cli_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "tx.csv") << "axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n1,NaN,0\n"
                                   "2,200,0\n";
  std::ofstream(dir / "case.toml")
      << "[calibration]\nbase = \"original\"\n[parameters]\nphi_c_deg = { lower = 25, upper = 40 "
         "}\n[[test]]\nname = \"tx\"\ntype = \"triaxial\"\ne0 = 0.6\ne0_at = \"initial-stress\"\n"
         "sigma3_kPa = 100\naxial_strain = 0.05\ndata = \"tx.csv\"\n";
  const Result r = run_pilempm("calibrate '" + (dir / "case.toml").string() + "' --out '" +
                               (dir / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("tx.csv:3: column \"q_kPa\""), std::string::npos) << r.output;
  fs::remove_all(dir);
}

}  // namespace
