// `pilempm mpm run` as a user runs it: the example column under self-weight, then its files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include "../support/mpm_case_texts.hpp"
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

// The Float64 values of a named DataArray of a .vtu written by pilempm (binary, UInt64 header).
std::vector<double> data_array(const std::string& vtu, const std::string& name) {
  const auto at = vtu.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const auto start = vtu.find('>', at) + 1;
  const auto end = vtu.find("</DataArray>", start);
  const std::vector<unsigned char> bytes = base64_decode(vtu.substr(start, end - start));
  std::uint64_t size = 0;
  std::memcpy(&size, bytes.data(), sizeof size);
  std::vector<double> values(size / sizeof(double));
  std::memcpy(values.data(), bytes.data() + sizeof size, size);
  return values;
}

// The DataSet entries of a .pvd, in order: timestep, part and file attributes as written.
struct PvdEntry {
  std::string time, part, file;
};
std::vector<PvdEntry> pvd_entries(const std::string& pvd) {
  auto attribute = [](const std::string& line, const std::string& name) {
    const auto at = line.find(name + "=\"");
    if (at == std::string::npos) return std::string();
    const auto start = at + name.size() + 2;
    return line.substr(start, line.find('"', start) - start);
  };
  std::vector<PvdEntry> entries;
  std::istringstream in(pvd);
  std::string line;
  while (std::getline(in, line))
    if (line.find("<DataSet") != std::string::npos)
      entries.push_back(
          {attribute(line, "timestep"), attribute(line, "part"), attribute(line, "file")});
  return entries;
}

std::string fmt_index(const std::string& stem, std::size_t index) {
  std::string digits = std::to_string(index);
  return stem + std::string(5 - std::min<std::size_t>(5, digits.size()), '0') + digits + ".vtu";
}

TEST(MpmCli, ColumnExampleWritesSnapshotsEnergiesAndTheWeightOfTheColumn) {
  const fs::path out = pilempm::test_support::fresh_temp_path("mpm-cli");
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
  for (const auto& entry : fs::directory_iterator(out))  // no temporary file is left
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();

  // energies.csv: a comment with the units, the header, then rows to t = 1 s.
  std::istringstream csv(read_text(out / "energies.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("per metre"), std::string::npos) << line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "time_s,step,dt_s,kinetic_J,internal_J,external_work_J,damping_J,contact_work_J,"
            "absorbed_J");
  std::string last;
  int rows = 0;
  while (std::getline(csv, line))
    if (!line.empty()) last = line, ++rows;
  EXPECT_GE(rows, 100);  // every output interval / 10
  double time = 0, dt = 0, kinetic = 0, internal = 0, external = 0, damping = 0, contact = 1,
         absorbed = 1;
  long step = 0;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%ld,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &time, &step, &dt,
                        &kinetic, &internal, &external, &damping, &contact, &absorbed),
            9)
      << last;
  EXPECT_EQ(contact, 0.0);   // no rigid bodies
  EXPECT_EQ(absorbed, 0.0);  // no absorbing boundaries
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
  EXPECT_EQ(bottom, 10);                         // 5 cells x 2 particles
  EXPECT_FALSE(fs::exists(out / "bodies.csv"));  // no rigid bodies
  EXPECT_NE(r.output.find("phase self-weight: ended at t = 1 s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("duration_s"), std::string::npos) << r.output;
  fs::remove_all(out);
}

// An elastic block in plane strain with a rigid plate on its surface: the plate is pushed down
// (with a velocity ramp) until it has moved 1 cm, which ends the first phase before its duration;
// then it is lifted until the soil's force on it falls below 1 kN/m, which ends the second.
std::string plate_case() {
  using namespace pilempm::test_support;
  return "title = \"plate on an elastic block\"\n" +
         mpm_case_opening({.solver = "local_damping = 0.1\nthreads = 1\n"}) +
         linear_elastic_material_text("elastic", 10.0) +
         mpm_region_text({.name = "block", .material = "elastic"}) + kPlateBodyText + R"([[phase]]
name = "push"
duration_s = 1.0
energy_interval_s = 0.01
stop_phase_displacement_y_m = -0.01
[phase.body.plate]
velocity_y_m_per_s = -0.1
ramp_s = 0.02
[[phase]]
name = "lift"
duration_s = 0.5
energy_interval_s = 0.01
stop_body = "plate"
stop_force_y_below_N = 1000.0
[phase.body.plate]
velocity_y_m_per_s = 0.1
)";
}

// The rows of a CSV file after its comment and header lines, split at commas.
std::vector<std::vector<std::string>> csv_rows(const std::string& text, std::string* header) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header != nullptr && header->empty()) {
      *header = line;
      continue;
    }
    std::vector<std::string> fields;
    std::string field;
    std::istringstream cells(line);
    while (std::getline(cells, field, ',')) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

TEST(MpmCli, PlatePushedToADisplacementThenLiftedToAForceWritesBodiesCsv) {
  const fs::path dir = pilempm::test_support::fresh_temp_path("mpm-plate");
  fs::create_directories(dir);
  std::ofstream(dir / "plate.toml") << plate_case();
  const Result r = run_pilempm("mpm run '" + (dir / "plate.toml").string() + "' --out '" +
                               (dir / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("phase push: ended at t = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stop_phase_displacement_y_m = -0.01: plate displacement y = -0.01 m"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("stop_force_y_below_N = 1000: plate force y = "), std::string::npos)
      << r.output;

  std::string header;
  const auto rows = csv_rows(read_text(dir / "out" / "bodies.csv"), &header);
  EXPECT_EQ(header,
            "time_s,step,phase,body,displacement_x_m,displacement_y_m,velocity_x_m_per_s,"
            "velocity_y_m_per_s,force_x_N,force_y_N,force_y_edge_0_N,force_y_edge_1_N,"
            "force_y_edge_2_N,force_y_edge_3_N");
  ASSERT_GT(rows.size(), 10u);
  double push_end = -1, push_force = 0, lift_end = -1, lift_displacement = 0, max_force = 0;
  double part_sum = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 14u);
    EXPECT_EQ(row[3], "plate");
    max_force = std::max(max_force, std::stod(row[9]));
    if (row[2] == "push") {
      push_end = std::stod(row[0]);
      push_force = std::stod(row[9]);
      EXPECT_GE(std::stod(row[5]), -0.01 - 1e-12);  // never beyond the goal
      part_sum = 0;
      for (std::size_t k = 10; k < 14; ++k) part_sum += std::stod(row[k]);
    } else {
      EXPECT_EQ(row[2], "lift");
      lift_end = std::stod(row[0]);
      lift_displacement = std::stod(row[5]);
    }
  }
  // The ramp: 0.5 mm over 0.02 s, then 9.5 mm at 0.1 m/s: 0.11 s.
  EXPECT_NEAR(push_end, 0.11, 2e-3);
  EXPECT_GT(push_force, 1000.0);  // the block pushes back
  EXPECT_NEAR(part_sum, push_force, 1e-6 * push_force);
  EXPECT_GT(lift_end, push_end);
  EXPECT_LT(lift_end, push_end + 0.5 - 1e-3);  // ended by the force rule, not the duration
  EXPECT_GT(lift_displacement, -0.01);         // it went back up
  EXPECT_GT(max_force, 1000.0);

  // The plate for ParaView: a bodies_NNNNN.vtu beside each particles_NNNNN.vtu, listed in
  // particles.pvd as part 1 at the same time; the last one holds the plate's polygon moved by
  // its last displacement in bodies.csv.
  const std::vector<PvdEntry> series = pvd_entries(read_text(dir / "out" / "particles.pvd"));
  ASSERT_GE(series.size(), 4u);
  ASSERT_EQ(series.size() % 2, 0u);
  for (std::size_t k = 0; k < series.size(); k += 2) {
    EXPECT_EQ(series[k].part, "0");
    EXPECT_EQ(series[k + 1].part, "1");
    EXPECT_EQ(series[k].time, series[k + 1].time);
    EXPECT_EQ(series[k].file, fmt_index("particles_", k / 2));
    EXPECT_EQ(series[k + 1].file, fmt_index("bodies_", k / 2));
  }
  const std::string bodies_vtu = read_text(dir / "out" / series.back().file);
  EXPECT_NE(bodies_vtu.find("NumberOfPoints=\"4\" NumberOfCells=\"1\""), std::string::npos);
  EXPECT_NE(bodies_vtu.find("Name=\"body\""), std::string::npos);
  const std::vector<double> points = data_array(bodies_vtu, "Points");
  ASSERT_EQ(points.size(), 12u);
  EXPECT_NEAR(std::stod(series.back().time), std::stod(rows.back()[0]), 1e-9);
  const double dx = std::stod(rows.back()[4]), dy = std::stod(rows.back()[5]);
  EXPECT_GT(std::abs(dy), 1e-4);  // it moved
  const double plate[4][2] = {{0.3, 0.5}, {0.7, 0.5}, {0.7, 0.6}, {0.3, 0.6}};
  for (const auto& v : plate) {
    bool found = false;
    for (std::size_t p = 0; p < 4; ++p)
      found =
          found || (std::abs(points[3 * p] - (v[0] + dx)) < 1e-9 &&
                    std::abs(points[3 * p + 1] - (v[1] + dy)) < 1e-9 && points[3 * p + 2] == 0.0);
    EXPECT_TRUE(found) << v[0] << ", " << v[1];
  }
  // At the end of the push the plate's underside is 1 cm lower.
  bool push_end_drawn = false;
  for (const PvdEntry& e : series)
    if (e.part == "1" && std::abs(std::stod(e.time) - push_end) < 1e-9) {
      const std::vector<double> at_end = data_array(read_text(dir / "out" / e.file), "Points");
      ASSERT_EQ(at_end.size(), 12u);
      double lowest = 1.0;
      for (std::size_t p = 0; p < 4; ++p) lowest = std::min(lowest, at_end[3 * p + 1]);
      EXPECT_NEAR(lowest, 0.49, 1e-5);
      push_end_drawn = true;
    }
  EXPECT_TRUE(push_end_drawn);

  // A checkpoint at each phase end; a restart from the first one ends with the same files.
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint_01_push.h5"));
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint_02_lift.h5"));
  const Result restarted = run_pilempm("mpm run '" + (dir / "plate.toml").string() + "' --out '" +
                                       (dir / "restarted").string() + "' --restart '" +
                                       (dir / "out" / "checkpoint_01_push.h5").string() + "'");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  EXPECT_NE(restarted.output.find("restarted from"), std::string::npos) << restarted.output;
  EXPECT_EQ(restarted.output.find("phase push: ended"), std::string::npos) << restarted.output;
  EXPECT_NE(restarted.output.find("phase lift: ended"), std::string::npos) << restarted.output;
  EXPECT_EQ(read_text(dir / "restarted" / "bodies.csv"), read_text(dir / "out" / "bodies.csv"));
  // The restarted series lists the first run's bodies too, as part 1.
  const std::vector<PvdEntry> resumed = pvd_entries(read_text(dir / "restarted" / "particles.pvd"));
  ASSERT_EQ(resumed.size(), series.size());
  for (std::size_t k = 0; k < resumed.size(); ++k) EXPECT_EQ(resumed[k].part, series[k].part);
  EXPECT_EQ(read_text(dir / "restarted" / "energies.csv"), read_text(dir / "out" / "energies.csv"));
  const Result missing =
      run_pilempm("mpm run '" + (dir / "plate.toml").string() + "' --out '" +
                  (dir / "again").string() + "' --restart '" + (dir / "none.h5").string() + "'");
  EXPECT_NE(missing.exit_code, 0) << missing.output;
  EXPECT_NE(missing.output.find("none.h5"), std::string::npos) << missing.output;

  // energies.csv has the contact work and the absorbed energy (the solver's balance with them
  // is tested in tests/mpm).
  std::string energies_header;
  const auto energies = csv_rows(read_text(dir / "out" / "energies.csv"), &energies_header);
  EXPECT_NE(energies_header.find(",contact_work_J,absorbed_J"), std::string::npos);
  ASSERT_FALSE(energies.empty());
  EXPECT_EQ(energies.back().size(), 9u);
  EXPECT_NEAR(std::stod(energies.back()[0]), lift_end, 1e-9);  // a row at each phase end
  int push_end_rows = 0;
  for (const auto& row : energies) {
    if (std::abs(std::stod(row[0]) - push_end) > 1e-9) continue;
    ++push_end_rows;
    EXPECT_GT(std::stod(row[7]), 0.0);  // the plate pushing down works on the soil
    EXPECT_EQ(std::stod(row[8]), 0.0);  // no absorbing boundaries
  }
  EXPECT_EQ(push_end_rows, 1);
  fs::remove_all(dir);
}

TEST(MpmCli, BadCaseFileIsReportedWithFileLineAndKey) {
  const fs::path dir = pilempm::test_support::fresh_temp_path("mpm-bad");
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
