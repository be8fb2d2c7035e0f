#pragma once
// ParaView output without VTK: point clouds as VTK XML UnstructuredGrid files (.vtu, one vertex
// cell per point, binary base64 data arrays) and time series as ParaView collections (.pvd).
// Format rules: VTK file formats, "XML File Formats", UnstructuredGrid; inline binary data is
// base64 of a UInt64 byte count (header_type="UInt64") followed by the raw little-endian values.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace pilempm {

/// One named field on the points: `components` values per point, point after point.
struct PointField {
  std::string name;
  int components = 1;          ///< 1 scalar, 3 vector, 9 tensor (ParaView's conventions)
  std::vector<double> values;  ///< size = points * components
};

/// Points (x, y, z) and their fields.
struct PointCloud {
  std::vector<double> coordinates;  ///< x0, y0, z0, x1, y1, z1, ...
  std::vector<PointField> fields;
  std::size_t size() const { return coordinates.size() / 3; }
};

/// The .vtu text of a point cloud. Throws Error when a field's size does not match.
std::string vtu_text(const PointCloud& cloud);

/// Writes the .vtu atomically.
void write_vtu(const std::filesystem::path& path, const PointCloud& cloud);

/// A time series of .vtu files for ParaView: add a snapshot, then write the .pvd (atomically;
/// file names are stored relative to the .pvd's folder).
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_path);
  void add(double time, const std::filesystem::path& vtu_path);
  void write() const;
  std::string text() const;

 private:
  std::filesystem::path pvd_path_;
  std::vector<std::pair<double, std::string>> entries_;
};

/// Base64 (RFC 4648) of raw bytes; exposed for tests.
std::string base64_encode(const unsigned char* data, std::size_t size);

}  // namespace pilempm
