#pragma once
// ParaView output without VTK: point clouds (one vertex cell per point) and polygons as VTK XML
// UnstructuredGrid files (.vtu, binary base64 data arrays), and time series as ParaView
// collections (.pvd; several parts at one time are the blocks of one multiblock data set).
// Format rules: VTK file formats, "XML File Formats", UnstructuredGrid; inline binary data is
// base64 of a UInt64 byte count (header_type="UInt64") followed by the raw little-endian values.
#include <cstdint>
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

/// Polygons: points (x, y, z) and, per polygon, its points' indices in order; fields per polygon.
struct PolygonMesh {
  std::vector<double> coordinates;         ///< x0, y0, z0, x1, y1, z1, ...
  std::vector<std::int64_t> connectivity;  ///< the point indices of polygon after polygon
  std::vector<std::int64_t> offsets;       ///< end of each polygon in `connectivity`
  std::vector<PointField> cell_fields;     ///< `components` values per polygon
  std::size_t size() const { return offsets.size(); }
};

/// The .vtu text of a point cloud. Throws Error when a field's size does not match.
std::string vtu_text(const PointCloud& cloud);
/// The .vtu text of polygons (VTK_POLYGON cells). Throws Error when a polygon has fewer than
/// three points, an index is out of range or a field's size does not match.
std::string vtu_text(const PolygonMesh& mesh);

/// Writes the .vtu atomically.
void write_vtu(const std::filesystem::path& path, const PointCloud& cloud);
void write_vtu(const std::filesystem::path& path, const PolygonMesh& mesh);

/// A time series of .vtu files for ParaView: add a snapshot, then write the .pvd (atomically;
/// file names are stored relative to the .pvd's folder). `part` numbers the data sets of one
/// time (ParaView reads parts 0, 1, ... as the blocks of a multiblock data set).
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_path);
  void add(double time, const std::filesystem::path& vtu_path, int part = 0);
  void write() const;
  std::string text() const;

 private:
  std::filesystem::path pvd_path_;
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  std::vector<Entry> entries_;
};

/// Base64 (RFC 4648) of raw bytes; exposed for tests.
std::string base64_encode(const unsigned char* data, std::size_t size);

}  // namespace pilempm
