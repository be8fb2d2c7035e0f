// The VTU/PVD writer follows VTK's XML format rules: checked by decoding what it wrote.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "pilempm/core/error.hpp"
#include "pilempm/io/vtu_writer.hpp"

namespace pilempm {
namespace {

std::string encode(const std::string& s) {
  return base64_encode(reinterpret_cast<const unsigned char*>(s.data()), s.size());
}

std::vector<unsigned char> decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  std::uint32_t buffer = 0;
  int bits = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;
    buffer = (buffer << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

// The decoded values of the DataArray called `name` (UInt64 byte count, then doubles).
std::vector<double> array_values(const std::string& vtu, const std::string& name) {
  // Name="NAME" ... format="binary">, then white space and the base64 text up to the next '<'.
  const std::size_t at = vtu.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t close = vtu.find('>', at);
  if (close == std::string::npos ||
      vtu.substr(at, close - at).find("format=\"binary\"") == std::string::npos)
    return {};
  const std::size_t start = vtu.find_first_not_of(" \t\r\n", close + 1);
  const std::size_t end = vtu.find_first_not_of(
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/=", start);
  if (start == std::string::npos || end == std::string::npos || end == start) return {};
  const std::vector<unsigned char> bytes = decode(vtu.substr(start, end - start));
  std::uint64_t count = 0;
  std::memcpy(&count, bytes.data(), sizeof(count));
  EXPECT_EQ(bytes.size(), sizeof(count) + count);
  std::vector<double> values(count / sizeof(double));
  std::memcpy(values.data(), bytes.data() + sizeof(count), count);
  return values;
}

TEST(VtuWriter, Base64MatchesRfc4648Vectors) {
  EXPECT_EQ(encode(""), "");
  EXPECT_EQ(encode("f"), "Zg==");
  EXPECT_EQ(encode("fo"), "Zm8=");
  EXPECT_EQ(encode("foo"), "Zm9v");
  EXPECT_EQ(encode("foob"), "Zm9vYg==");
  EXPECT_EQ(encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
}

TEST(VtuWriter, PointsAndFieldsRoundTrip) {
  PointCloud cloud;
  cloud.coordinates = {0.0, 0.0, 0.0, 1.5, -2.0, 0.0, 3.25, 4.0, 0.0};
  cloud.fields.push_back({"void_ratio", 1, {0.6, 0.7, 0.8}});
  cloud.fields.push_back({"velocity_m_per_s", 3, {1, 2, 3, 4, 5, 6, 7, 8, 9}});
  const std::string vtu = vtu_text(cloud);
  EXPECT_NE(vtu.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(vtu.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(vtu.find("NumberOfPoints=\"3\" NumberOfCells=\"3\""), std::string::npos);
  EXPECT_EQ(array_values(vtu, "Points"), cloud.coordinates);
  EXPECT_EQ(array_values(vtu, "void_ratio"), cloud.fields[0].values);
  EXPECT_EQ(array_values(vtu, "velocity_m_per_s"), cloud.fields[1].values);
  EXPECT_NE(vtu.find("Name=\"velocity_m_per_s\" NumberOfComponents=\"3\""), std::string::npos);
  // Every element that opens is closed.
  for (const char* tag : {"VTKFile", "UnstructuredGrid", "Piece", "PointData", "Points", "Cells"})
    EXPECT_NE(vtu.find(std::string("</") + tag + ">"), std::string::npos) << tag;
}

TEST(VtuWriter, FieldOfWrongSizeIsAnError) {
  PointCloud cloud;
  cloud.coordinates = {0, 0, 0, 1, 1, 0};
  cloud.fields.push_back({"p_kPa", 1, {1.0}});
  EXPECT_THROW(vtu_text(cloud), Error);
}

TEST(VtuWriter, PolygonsAreVtkPolygonCellsWithCellFields) {
  PolygonMesh mesh;
  mesh.coordinates = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0};
  mesh.connectivity = {0, 1, 2, 3, 1, 4, 2};
  mesh.offsets = {4, 7};
  mesh.cell_fields.push_back({"body", 1, {0.0, 1.0}});
  const std::string vtu = vtu_text(mesh);
  EXPECT_NE(vtu.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos) << vtu;
  EXPECT_NE(vtu.find("<CellData>"), std::string::npos);
  EXPECT_EQ(array_values(vtu, "body"), (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(array_values(vtu, "Points"), mesh.coordinates);
  // types: UInt8 7 (VTK_POLYGON) twice, after the UInt64 byte count 2.
  const std::size_t at = vtu.find("Name=\"types\"");
  ASSERT_NE(at, std::string::npos);
  const std::size_t start = vtu.find_first_not_of(" \t\r\n", vtu.find('>', at) + 1);
  const std::vector<unsigned char> types = decode(vtu.substr(start, vtu.find('<', start) - start));
  EXPECT_EQ(types, (std::vector<unsigned char>{2, 0, 0, 0, 0, 0, 0, 0, 7, 7}));

  PolygonMesh bad = mesh;
  bad.offsets = {2, 7};  // a polygon of two points
  EXPECT_THROW(vtu_text(bad), Error);
  bad = mesh;
  bad.connectivity[6] = 5;  // no point 5
  EXPECT_THROW(vtu_text(bad), Error);
  bad = mesh;
  bad.offsets = {4};  // indices left over
  EXPECT_THROW(vtu_text(bad), Error);
  bad = mesh;
  bad.cell_fields[0].values.pop_back();
  EXPECT_THROW(vtu_text(bad), Error);
}

TEST(VtuWriter, PvdPartsNumberTheDataSetsOfOneTime) {
  PvdSeries series("/tmp/run/particles.pvd");
  series.add(0.5, "/tmp/run/particles_00001.vtu");
  series.add(0.5, "/tmp/run/bodies_00001.vtu", 1);
  const std::string text = series.text();
  EXPECT_NE(text.find("timestep=\"0.5\" part=\"0\" file=\"particles_00001.vtu\""),
            std::string::npos);
  EXPECT_NE(text.find("timestep=\"0.5\" part=\"1\" file=\"bodies_00001.vtu\""), std::string::npos);
}

TEST(VtuWriter, PvdListsSnapshotsRelativeToItsFolder) {
  PvdSeries series("/tmp/run/fields.pvd");
  series.add(0.0, "/tmp/run/fields/step_0.vtu");
  series.add(0.25, "/tmp/run/fields/step_1.vtu");
  const std::string text = series.text();
  EXPECT_NE(text.find("type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("timestep=\"0.25\" part=\"0\" file=\"fields/step_1.vtu\""),
            std::string::npos);
}

}  // namespace
}  // namespace pilempm
