#include "pilempm/io/vtu_writer.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {

std::string base64_encode(const unsigned char* data, std::size_t size) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t v = (std::uint32_t{data[i]} << 16) | (std::uint32_t{data[i + 1]} << 8) |
                            std::uint32_t{data[i + 2]};
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < size) {
    std::uint32_t v = std::uint32_t{data[i]} << 16;
    if (i + 1 < size) v |= std::uint32_t{data[i + 1]} << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

// A binary DataArray: base64 of [UInt64 byte count][values] (header_type="UInt64": a 32-bit
// count would wrap silently above 4 GiB per array).
template <typename T>
std::string encoded(const std::vector<T>& values) {
  const auto bytes = static_cast<std::uint64_t>(values.size() * sizeof(T));
  std::vector<unsigned char> buffer(sizeof(std::uint64_t) + bytes);
  std::memcpy(buffer.data(), &bytes, sizeof(bytes));
  if (bytes > 0) std::memcpy(buffer.data() + sizeof(bytes), values.data(), bytes);
  return base64_encode(buffer.data(), buffer.size());
}

template <typename T>
void data_array(std::string& out, const char* type, std::string_view name, int components,
                const std::vector<T>& values) {
  out += fmt::format(
      "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
      "format=\"binary\">\n          {}\n        </DataArray>\n",
      type, name, components, encoded(values));
}

std::string xml_escaped(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

namespace {

void check_fields(const std::vector<PointField>& fields, std::size_t count, const char* what) {
  for (const PointField& f : fields)
    if (f.components < 1 || f.values.size() != count * static_cast<std::size_t>(f.components))
      throw Error(fmt::format("VTU output: field \"{}\" has {} values for {} {} x {} components",
                              f.name, f.values.size(), count, what, f.components));
}

// An UnstructuredGrid of one piece: points, cells (connectivity, offsets, types) and fields.
std::string unstructured_text(const std::vector<double>& coordinates,
                              const std::vector<PointField>& point_fields,
                              const std::vector<PointField>& cell_fields,
                              const std::vector<std::int64_t>& connectivity,
                              const std::vector<std::int64_t>& offsets,
                              const std::vector<std::uint8_t>& types) {
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                     coordinates.size() / 3, offsets.size());
  out += "      <PointData>\n";
  for (const PointField& f : point_fields)
    data_array(out, "Float64", xml_escaped(f.name), f.components, f.values);
  out += "      </PointData>\n";
  if (!cell_fields.empty()) {
    out += "      <CellData>\n";
    for (const PointField& f : cell_fields)
      data_array(out, "Float64", xml_escaped(f.name), f.components, f.values);
    out += "      </CellData>\n";
  }
  out += "      <Points>\n";
  data_array(out, "Float64", "Points", 3, coordinates);
  out += "      </Points>\n";
  out += "      <Cells>\n";
  data_array(out, "Int64", "connectivity", 1, connectivity);
  data_array(out, "Int64", "offsets", 1, offsets);
  data_array(out, "UInt8", "types", 1, types);
  out += "      </Cells>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace

std::string vtu_text(const PointCloud& cloud) {
  if (cloud.coordinates.size() % 3 != 0)
    throw Error(
        fmt::format("VTU output: {} coordinates is not a multiple of 3", cloud.coordinates.size()));
  const std::size_t n = cloud.size();
  check_fields(cloud.fields, n, "points");
  // One VTK_VERTEX (type 1) cell per point.
  std::vector<std::int64_t> connectivity(n), offsets(n);
  std::vector<std::uint8_t> types(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  return unstructured_text(cloud.coordinates, cloud.fields, {}, connectivity, offsets, types);
}

std::string vtu_text(const PolygonMesh& mesh) {
  if (mesh.coordinates.size() % 3 != 0)
    throw Error(
        fmt::format("VTU output: {} coordinates is not a multiple of 3", mesh.coordinates.size()));
  const auto points = static_cast<std::int64_t>(mesh.coordinates.size() / 3);
  std::int64_t begin = 0;
  for (const std::int64_t end : mesh.offsets) {
    if (end - begin < 3 || end > static_cast<std::int64_t>(mesh.connectivity.size()))
      throw Error(fmt::format("VTU output: a polygon from {} to {} of {} indices", begin, end,
                              mesh.connectivity.size()));
    begin = end;
  }
  if (begin != static_cast<std::int64_t>(mesh.connectivity.size()))
    throw Error(fmt::format("VTU output: the polygons end at {} of {} indices", begin,
                            mesh.connectivity.size()));
  for (const std::int64_t index : mesh.connectivity)
    if (index < 0 || index >= points)
      throw Error(fmt::format("VTU output: point index {} of {} points", index, points));
  check_fields(mesh.cell_fields, mesh.size(), "polygons");
  // VTK_POLYGON (type 7) cells.
  const std::vector<std::uint8_t> types(mesh.size(), 7);
  return unstructured_text(mesh.coordinates, {}, mesh.cell_fields, mesh.connectivity, mesh.offsets,
                           types);
}

void write_vtu(const std::filesystem::path& path, const PointCloud& cloud) {
  write_file_atomically(path, vtu_text(cloud));
}

void write_vtu(const std::filesystem::path& path, const PolygonMesh& mesh) {
  write_file_atomically(path, vtu_text(mesh));
}

PvdSeries::PvdSeries(std::filesystem::path pvd_path) : pvd_path_(std::move(pvd_path)) {}

void PvdSeries::add(double time, const std::filesystem::path& vtu_path, int part) {
  const std::filesystem::path folder = pvd_path_.parent_path();
  const std::filesystem::path relative =
      folder.empty() ? vtu_path : vtu_path.lexically_relative(folder);
  entries_.push_back({time, part, relative.generic_string()});
}

std::string PvdSeries::text() const {
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  out += "  <Collection>\n";
  for (const Entry& e : entries_)
    out += fmt::format("    <DataSet timestep=\"{}\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part,
                       xml_escaped(e.file));
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

void PvdSeries::write() const {
  write_file_atomically(pvd_path_, text());
}

}  // namespace pilempm
