// Calibration case files and measured curves: a good case reads into the problem it describes,
// and bad data stop with an error naming the file, the line and the column.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "pilempm/io/calibration_case.hpp"

namespace {

namespace fs = std::filesystem;
using namespace pilempm;

class CalibrationCaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pilempm_calibration_case_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }
  CalibrationCase parse(const std::string& text) {
    return parse_calibration_case(text, (dir_ / "case.toml").string(), dir_);
  }
  // The message of the InputError that reading `csv` as tx.csv gives ("" when none).
  std::string error_of(const std::string& csv, const std::string& extra_keys = "") {
    write("tx.csv", csv);
    try {
      parse(kHead + kTriaxial + extra_keys);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  static inline const std::string kHead = R"(
[calibration]
base = "original"
igs = "IGS3"
[parameters]
phi_c_deg = { lower = 25, upper = 40 }
alpha = { lower = 0.01, upper = 0.5, start = 0.1 }
beta = 1.05
)";
  static inline const std::string kTriaxial = R"(
[[test]]
name = "tx"
type = "triaxial"
e0 = 0.6
e0_at = "initial-stress"
sigma3_kPa = 100
axial_strain = 0.1
steps = 50
data = "tx.csv"
)";
  static inline const std::string kGoodCsv =
      "# a comment\naxial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n2,300,0.1\n5,350,-1\n"
      "10,320,-3\n";
  fs::path dir_;
};

TEST_F(CalibrationCaseTest, AGoodCaseReadsIntoItsProblem) {
  write("tx.csv", kGoodCsv);
  const CalibrationCase c = parse(kHead + kTriaxial);
  const auto& p = c.problem;
  ASSERT_EQ(p.free.size(), 2u);
  EXPECT_EQ(p.free[0].id, calibration::ParameterId::phi_c_deg);
  EXPECT_EQ(p.free[1].start, 0.1);
  EXPECT_DOUBLE_EQ(p.base.hypoplastic.beta, 1.05);
  EXPECT_DOUBLE_EQ(p.base.igs.R, 1e-4);
  ASSERT_EQ(p.tests.size(), 1u);
  const auto& t = p.tests[0];
  EXPECT_EQ(t.abscissa, (std::vector<double>{0, 2, 5, 10}));
  ASSERT_EQ(t.quantities.size(), 2u);
  EXPECT_EQ(t.quantities[0].column, "q_kPa");
  EXPECT_EQ(t.quantities[1].values, (std::vector<double>{0, 0.1, -1, -3}));
  EXPECT_TRUE(c.warnings.empty());
}

TEST_F(CalibrationCaseTest, AMissingColumnIsNamedWithTheHeader) {
  const std::string e = error_of("axial_strain_pct,q_kPa\n0,0\n1,100\n2,150\n");
  EXPECT_NE(e.find("tx.csv:1"), std::string::npos) << e;
  EXPECT_NE(e.find("column \"volumetric_strain_pct\""), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
}

TEST_F(CalibrationCaseTest, AMisnamedColumnGetsAGuessWithItsUnit) {
  const std::string e = error_of(
      "# header on line 2\naxial_strain_pct,q_Pa,volumetric_strain_pct\n0,0,0\n1,1,1\n2,2,2\n");
  EXPECT_NE(e.find("tx.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("column \"q_Pa\""), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean \"q_kPa\""), std::string::npos) << e;
}

TEST_F(CalibrationCaseTest, NaNIsAnErrorAtItsLineAndColumn) {
  const std::string e =
      error_of("axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n1,nan,0\n2,150,0\n");
  EXPECT_NE(e.find("tx.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("column \"q_kPa\""), std::string::npos) << e;
  EXPECT_NE(e.find("NaN"), std::string::npos) << e;
}

TEST_F(CalibrationCaseTest, StrainsInFractionsAreCaught) {
  const std::string e = error_of(
      "axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n0.02,300,0\n0.05,350,0\n0.1,320,0\n");
  EXPECT_NE(e.find("tx.csv:5"), std::string::npos) << e;
  EXPECT_NE(e.find("column \"axial_strain_pct\""), std::string::npos) << e;
  EXPECT_NE(e.find("per cent, not fractions"), std::string::npos) << e;
}

TEST_F(CalibrationCaseTest, StressesInPaAreCaught) {
  write("oed.csv", "sigma_a_kPa,void_ratio\n10000,0.7\n100000,0.69\n400000,0.68\n");
  try {
    parse(kHead + R"(
[[test]]
name = "oed"
type = "oedometer"
e0 = 0.7
e0_at = "initial-stress"
sigma_v0_kPa = 10
sigma_v_kPa = 400
data = "oed.csv"
)");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("oed.csv:4"), std::string::npos) << m;
    EXPECT_NE(m.find("column \"sigma_a_kPa\""), std::string::npos) << m;
    EXPECT_NE(m.find("in Pa"), std::string::npos) << m;
  }
}

TEST_F(CalibrationCaseTest, NonMonotonicLoadingIsAnErrorWhereItFalls) {
  const std::string e =
      error_of("axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n4,300,0\n3,350,0\n10,320,0\n");
  EXPECT_NE(e.find("tx.csv:4"), std::string::npos) << e;
  EXPECT_NE(e.find("not monotonic"), std::string::npos) << e;
}

TEST_F(CalibrationCaseTest, TooFewPointsAndTooFewDataForTheParameters) {
  std::string e = error_of("axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n5,300,0\n");
  EXPECT_NE(e.find("too few points"), std::string::npos) << e;
  EXPECT_NE(e.find("tx.csv"), std::string::npos) << e;
  // 3 rows x 2 quantities = 6 values are enough for 2 free parameters, not for 3 more.
  const std::string three_rows =
      "axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n5,300,0\n10,320,0\n";
  EXPECT_EQ(error_of(three_rows), "");
  write("tx.csv", three_rows);
  std::string head = kHead;
  head.replace(head.find("beta = 1.05"), 11,
               "beta = { lower = 0.5, upper = 2 }\nn = { lower = 0.2, upper = 0.7 }\ne_c0 = { "
               "lower = 0.7, upper = 1.1 }");
  try {
    parse(head + kTriaxial);
    FAIL() << "no error";
  } catch (const InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("too few data: 6 measured values for 5 free"),
              std::string::npos)
        << ex.what();
  }
}

TEST_F(CalibrationCaseTest, DataBeyondTheProgrammeAndUnknownKeysAreErrors) {
  std::string e = error_of(
      "axial_strain_pct,q_kPa,volumetric_strain_pct\n0,0,0\n5,300,0\n10,320,0\n15,320,0\n");
  EXPECT_NE(e.find("beyond the test's programme"), std::string::npos) << e;
  write("tx.csv", kGoodCsv);
  try {
    parse(kHead + kTriaxial + "weigth = 2\n");
    FAIL() << "no error";
  } catch (const InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("weigth"), std::string::npos) << ex.what();
  }
}

TEST_F(CalibrationCaseTest, IgsParametersNeedTheIntergranularStrainOn) {
  write("tx.csv", kGoodCsv);
  std::string head = kHead;
  head.replace(head.find("igs = \"IGS3\""), 12, "igs = \"none\"");
  try {
    parse(head + "m_R = { lower = 2, upper = 8 }\n" + kTriaxial);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m_R"), std::string::npos) << e.what();
  }
}

}  // namespace
