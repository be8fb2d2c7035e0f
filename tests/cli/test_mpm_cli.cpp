// `pilempm mpm run` as a user runs it: the example column under self-weight, then its files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include "run_pilempm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using pilempm_test::read_text;
using pilempm_test::Result;
using pilempm_test::run_pilempm;

namespace fs = std::filesystem;

std::vector<unsigned char> base64_decode(const std::string& text) {
  std::vector<unsigned char> out;
  unsigned value = 0;
  int bits = 0;
  for (char c : text) {
    int digit;
    if (c >= 'A' && c <= 'Z')
      digit = c - 'A';
    else if (c >= 'a' && c <= 'z')
      digit = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      digit = c - '0' + 52;
    else if (c == '+')
      digit = 62;
    else if (c == '/')
      digit = 63;
    else
      continue;  // '=' and white space
    value = (value << 6) | static_cast<unsigned>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((value >> bits) & 0xFFu));
    }
  }
  return out;
}

// The Float64 values of a named DataArray of a .vtu written by pilempm (binary, UInt32 header).
std::vector<double> data_array(const std::string& vtu, const std::string& name) {
  const auto at = vtu.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const auto start = vtu.find('>', at) + 1;
  const auto end = vtu.find("</DataArray>", start);
  const std::vector<unsigned char> bytes = base64_decode(vtu.substr(start, end - start));
  std::uint32_t size = 0;
  std::memcpy(&size, bytes.data(), sizeof size);
  std::vector<double> values(size / sizeof(double));
  std::memcpy(values.data(), bytes.data() + sizeof size, size);
  return values;
}

TEST(MpmCli, ColumnExampleWritesSnapshotsEnergiesAndTheWeightOfTheColumn) {
  const fs::path out =
      fs::temp_directory_path() / ("pilempm-mpm-cli-" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string example =
      std::string(PILEMPM_SOURCE_DIR) + "/examples/mpm/column_self_weight.toml";
  const Result r = run_pilempm("mpm run '" + example + "' --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("mpm: phase self-weight"), std::string::npos) << r.output;

  // The series: 11 snapshots (t = 0, 0.1, ..., 1 s), each listed in the .pvd.
  const std::string pvd = read_text(out / "particles.pvd");
  EXPECT_NE(pvd.find("<VTKFile type=\"Collection\""), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("</VTKFile>"), std::string::npos);
  std::vector<fs::path> vtus;
  for (const auto& entry : fs::directory_iterator(out))
    if (entry.path().extension() == ".vtu") vtus.push_back(entry.path());
  std::sort(vtus.begin(), vtus.end());
  ASSERT_EQ(vtus.size(), 11u);
  for (const fs::path& vtu : vtus) {
    EXPECT_NE(pvd.find(vtu.filename().string()), std::string::npos) << vtu;
    const std::string text = read_text(vtu);
    EXPECT_EQ(text.rfind("<?xml", 0), 0u) << vtu;
    EXPECT_NE(text.find("</VTKFile>"), std::string::npos) << vtu;
  }
  EXPECT_FALSE(fs::exists(out / "energies.csv.tmp"));

  // energies.csv: a comment with the units, the header, then rows to t = 1 s.
  std::istringstream csv(read_text(out / "energies.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("per metre"), std::string::npos) << line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time_s,step,dt_s,kinetic_J,internal_J,external_work_J,damping_J");
  std::string last;
  int rows = 0;
  while (std::getline(csv, line))
    if (!line.empty()) last = line, ++rows;
  EXPECT_GE(rows, 100);  // every output interval / 10
  double time = 0, dt = 0, kinetic = 0, internal = 0, external = 0, damping = 0;
  long step = 0;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%ld,%lf,%lf,%lf,%lf,%lf", &time, &step, &dt, &kinetic,
                        &internal, &external, &damping),
            7)
      << last;
  EXPECT_NEAR(time, 1.0, 1e-9);
  EXPECT_GT(step, 100);
  EXPECT_LT(kinetic, 1e-6 * internal);  // at rest
  // The energy account closes to the solver's accuracy (tests/mpm: within 1 %).
  EXPECT_NEAR(kinetic + internal + damping, external, 1e-2 * external);

  // At rest, the vertical stress at the bottom particles is the weight of the column, ρ g H.
  const std::string final_vtu = read_text(vtus.back());
  const std::vector<double> points = data_array(final_vtu, "Points");
  const std::vector<double> stress = data_array(final_vtu, "stress_kPa_compression_positive");
  ASSERT_EQ(stress.size(), 3 * points.size());
  const std::size_t n = points.size() / 3;
  ASSERT_EQ(n, 400u);
  double lowest = 1e9;
  for (std::size_t p = 0; p < n; ++p) lowest = std::min(lowest, points[3 * p + 1]);
  const double weight_kPa = 2000.0 * 9.81 * 2.0 / 1000.0;
  int bottom = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (points[3 * p + 1] > lowest + 0.01) continue;
    ++bottom;
    EXPECT_NEAR(stress[9 * p + 4], weight_kPa, 0.05 * weight_kPa) << "particle " << p;
    // Oedometric: σ_xx = ν / (1 - ν) σ_yy, compression positive.
    EXPECT_NEAR(stress[9 * p + 0], 0.3 / 0.7 * stress[9 * p + 4], 0.05 * weight_kPa);
  }
  EXPECT_EQ(bottom, 10);  // 5 cells x 2 particles
  fs::remove_all(out);
}

TEST(MpmCli, BadCaseFileIsReportedWithFileLineAndKey) {
  const fs::path dir =
      fs::temp_directory_path() / ("pilempm-mpm-bad-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text =
      read_text(std::string(PILEMPM_SOURCE_DIR) + "/examples/mpm/column_self_weight.toml");
  text.replace(text.find("courant_number"), 14, "courant_numbre");
  std::ofstream(dir / "bad.toml") << text;
  const Result r = run_pilempm("mpm run '" + (dir / "bad.toml").string() + "' --out '" +
                               (dir / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.toml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("courant_numbre"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "particles.pvd"));
  fs::remove_all(dir);
}

}  // namespace
