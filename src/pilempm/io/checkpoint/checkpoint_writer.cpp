// Writing the MPM checkpoint (io/mpm_checkpoint.hpp; the layout in checkpoint_layout.hpp).
#include <fcntl.h>
#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <utility>

#include "pilempm/core/error.hpp"
#include "pilempm/io/checkpoint/checkpoint_layout.hpp"
#include "pilempm/io/checkpoint/hdf5_handles.hpp"
#include "pilempm/io/mpm_checkpoint.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {

namespace fs = std::filesystem;
using mpm::Particles;
using mpm::RigidBody;
using mpm::Vec2;
using namespace checkpoint;

namespace {

class Writer {
 public:
  explicit Writer(std::string file) : file_(std::move(file)) {}

  Handle create_file() const {
    // The latest format: its metadata carries checksums (see the layout above).
    const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (!access.valid() ||
        H5Pset_libver_bounds(access.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST) < 0)
      fail_hdf5("the file access properties");
    Handle file(H5Fcreate(file_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    if (!file.valid()) {
      const int saved = errno;
      fail(fmt::format("cannot create it: {}",
                       saved != 0 ? std::string(std::strerror(saved)) : hdf5_error_text()));
    }
    return file;
  }

  Handle group(hid_t parent, const char* name) const {
    Handle g(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid()) fail_hdf5(fmt::format("group {}", name));
    return g;
  }

  void attribute(hid_t loc, const char* name, hid_t memory_type, const void* value) const {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle attr;
    if (space.valid())
      attr = Handle(H5Acreate2(loc, name, memory_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose);
    if (!attr.valid() || H5Awrite(attr.get(), memory_type, value) < 0)
      fail_hdf5(fmt::format("attribute {}", name));
  }
  void attribute(hid_t loc, const char* name, double value) const {
    attribute(loc, name, H5T_NATIVE_DOUBLE, &value);
  }
  void attribute(hid_t loc, const char* name, std::int64_t value) const {
    attribute(loc, name, H5T_NATIVE_INT64, &value);
  }
  void attribute(hid_t loc, const char* name, const std::string& value) const {
    const Handle type = string_type(value.size());
    if (!type.valid()) fail_hdf5(fmt::format("attribute {}", name));
    std::string padded = value;
    padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
    attribute(loc, name, type.get(), padded.data());
  }

  // A dataset of `dims` from `data` (of the memory type; nothing is read when it is empty).
  void dataset(hid_t loc, const char* name, hid_t memory_type, const std::vector<hsize_t>& dims,
               const void* data) const {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
    Handle set;
    if (space.valid())
      set = Handle(
          H5Dcreate2(loc, name, memory_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          H5Dclose);
    const bool empty = std::find(dims.begin(), dims.end(), hsize_t{0}) != dims.end();
    if (!set.valid() ||
        (!empty && H5Dwrite(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
      fail_hdf5(fmt::format("dataset {}", name));
    checksum(set.get(), empty ? nullptr : data, empty ? 0 : byte_count(memory_type, dims));
  }
  // The checksum attribute of a dataset whose bytes (as written) are `data`.
  void checksum(hid_t set, const void* data, std::size_t size) const {
    const std::uint64_t hash = content_hash(data, size);
    attribute(set, "checksum", H5T_NATIVE_UINT64, &hash);
  }
  void doubles(hid_t loc, const char* name, const std::vector<hsize_t>& dims,
               const std::vector<double>& values) const {
    dataset(loc, name, H5T_NATIVE_DOUBLE, dims, values.data());
  }
  void points(hid_t loc, const char* name, const std::vector<Vec2>& values) const {
    doubles(loc, name, {values.size(), 2}, flatten(values));
  }
  void vector(hid_t loc, const char* name, const Vec2& value) const {
    doubles(loc, name, {2}, {value.x(), value.y()});
  }
  // A string of any bytes as a scalar dataset, with its length as an attribute.
  void text(hid_t loc, const char* name, const std::string& value) const {
    const Handle type = string_type(value.size());
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle set;
    if (type.valid() && space.valid())
      set = Handle(
          H5Dcreate2(loc, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
          H5Dclose);
    std::string padded = value;
    padded.resize(std::max<std::size_t>(value.size(), 1), '\0');
    if (!set.valid() ||
        H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()) < 0)
      fail_hdf5(fmt::format("dataset {}", name));
    attribute(set.get(), "length", static_cast<std::int64_t>(value.size()));
    checksum(set.get(), padded.data(), padded.size());
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw Error(fmt::format("cannot write checkpoint {}: {}", file_, why));
  }
  [[noreturn]] void fail_hdf5(const std::string& what) const {
    const std::string detail = hdf5_error_text();
    fail(fmt::format("HDF5 could not write {}{}", what, detail.empty() ? "" : ": " + detail));
  }

 private:
  std::string file_;
};

void write_particles(const Writer& w, hid_t root, const Particles& particles,
                     const std::vector<ModelPtr>& models) {
  const Handle group = w.group(root, "particles");
  const std::size_t n = particles.size();
  std::vector<double> values;
  for (const ParticleField& field : particle_fields()) {
    const std::size_t width = field.width();
    values.assign(n * width, 0.0);
    for (std::size_t p = 0; p < n; ++p) field.get(particles, p, &values[p * width]);
    std::vector<hsize_t> dims{n};
    dims.insert(dims.end(), field.value_dims.begin(), field.value_dims.end());
    w.doubles(group.get(), field.name, dims, values);
  }
  w.dataset(group.get(), "material", H5T_NATIVE_INT, {n}, particles.material.data());
  const Handle history = w.group(group.get(), "history");
  for (const HistoryDataset& d : history_datasets(models)) {
    const std::size_t size = static_cast<std::size_t>(d.size);
    values.assign(n * size, 0.0);
    for (std::size_t p = 0; p < n; ++p) {
      const HistoryVariable* v =
          find_history(*models[static_cast<std::size_t>(particles.material[p])], d.name);
      if (v == nullptr) continue;
      const double* from = particles.state[p].history.data() + v->offset;
      std::copy(from, from + size, &values[p * size]);
    }
    w.doubles(history.get(), d.name.c_str(), {n, size}, values);
  }
}

void write_bodies(const Writer& w, hid_t root, const mpm::MpmState& solver,
                  const mpm::SolverRunState& state) {
  const Handle group = w.group(root, "bodies");
  for (int b = 0; b < solver.rigid_body_count(); ++b) {
    const RigidBody& body = solver.rigid_body(b);
    const Handle g = w.group(group.get(), std::to_string(b).c_str());
    w.attribute(g.get(), "kind", std::string(body.axisymmetric() ? "pile" : "polygon"));
    w.attribute(g.get(), "part_count", static_cast<std::int64_t>(body.part_count()));
    w.attribute(g.get(), "friction", body.friction());
    w.attribute(g.get(), "contact_distance", body.contact_distance());
    w.points(g.get(), "vertices", body.vertices());
    w.vector(g.get(), "displacement", body.displacement());
    w.vector(g.get(), "velocity", body.velocity());
    const mpm::RigidBodyForce& force = state.rigid_body_forces.at(static_cast<std::size_t>(b));
    w.vector(g.get(), "contact_force", force.total);
    w.points(g.get(), "contact_force_parts", force.parts);
  }
}

void write_run_state(const Writer& w, hid_t root, const mpm::SolverRunState& state) {
  const Handle g = w.group(root, "run_state");
  w.attribute(g.get(), "time", state.time);
  w.attribute(g.get(), "steps", static_cast<std::int64_t>(state.steps));
  w.attribute(g.get(), "max_wave_speed", state.max_wave_speed);
  w.attribute(g.get(), "wave_speed_step", static_cast<std::int64_t>(state.wave_speed_step));
  w.attribute(g.get(), "max_particle_speed", state.max_particle_speed);
  const Handle e = w.group(g.get(), "energies");
  const mpm::Energies& energies = state.energies;
  w.attribute(e.get(), "kinetic", energies.kinetic);
  w.attribute(e.get(), "internal", energies.internal);
  w.attribute(e.get(), "external_work", energies.external_work);
  w.attribute(e.get(), "damping", energies.damping);
  w.attribute(e.get(), "contact_work", energies.contact_work);
  w.attribute(e.get(), "absorbed", energies.absorbed);
  if (state.scheme_arrays.empty()) return;
  // The analysis's own arrays, by index, each with its name.
  const Handle arrays = w.group(g.get(), "scheme");
  w.attribute(arrays.get(), "count", static_cast<std::int64_t>(state.scheme_arrays.size()));
  std::int64_t index = 0;
  for (const auto& [name, values] : state.scheme_arrays) {
    const std::string key = std::to_string(index++);
    w.doubles(arrays.get(), key.c_str(), {values.size()}, values);
    const Handle set(H5Dopen2(arrays.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) w.fail_hdf5(fmt::format("dataset run_state/scheme/{}", key));
    w.attribute(set.get(), "name", name);
  }
}

void write_run_info(const Writer& w, hid_t root, const MpmCheckpointInfo& info) {
  const Handle g = w.group(root, "run");
  w.attribute(g.get(), "case_source", info.case_source);
  w.attribute(g.get(), "next_phase", static_cast<std::int64_t>(info.next_phase));
  w.attribute(g.get(), "phase_start", info.phase_start);
  w.points(g.get(), "initial_position", info.initial_position);
  const Handle records = w.group(g.get(), "records");
  w.attribute(records.get(), "count", static_cast<std::int64_t>(info.records.size()));
  std::int64_t index = 0;
  for (const auto& [name, content] : info.records) {
    const std::string key = std::to_string(index++);
    w.text(records.get(), key.c_str(), content);
    const Handle set(H5Dopen2(records.get(), key.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) w.fail_hdf5(fmt::format("dataset run/records/{}", key));
    w.attribute(set.get(), "name", name);
  }
}

void write_checkpoint_file(const Writer& w, const mpm::MpmState& solver,
                           const MpmCheckpointInfo& info) {
  const std::size_t n = solver.particles().size();
  if (!info.initial_position.empty() && info.initial_position.size() != n)
    w.fail(fmt::format("initial_position has {} entries: must be 0 or the particle count {}",
                       info.initial_position.size(), n));
  const mpm::SolverRunState state = solver.run_state();
  Handle file = w.create_file();
  {
    const Handle root(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose);
    if (!root.valid()) w.fail_hdf5("the root group");
    const hid_t r = root.get();
    w.attribute(r, "format", std::string(kFormat));
    w.attribute(r, "format_version", std::int64_t{kMpmCheckpointFormatVersion});
    w.attribute(r, "geometry", std::string(geometry_name(solver.geometry())));
    w.attribute(r, "analysis", std::string(solver.analysis()));
    w.attribute(r, "grid_nx", std::int64_t{solver.grid().nx()});
    w.attribute(r, "grid_ny", std::int64_t{solver.grid().ny()});
    w.attribute(r, "particle_count", static_cast<std::int64_t>(n));
    w.attribute(r, "materials_count", static_cast<std::int64_t>(solver.materials().size()));
    w.attribute(r, "body_count", std::int64_t{solver.rigid_body_count()});
    w.attribute(r, "threads", std::int64_t{solver.threads()});
    const Handle grid = w.group(r, "grid");
    const std::vector<double>& x = solver.grid().x_axis().nodes();
    const std::vector<double>& y = solver.grid().y_axis().nodes();
    w.doubles(grid.get(), "x_nodes", {x.size()}, x);
    w.doubles(grid.get(), "y_nodes", {y.size()}, y);
    write_particles(w, r, solver.particles(), solver.materials());
    write_bodies(w, r, solver, state);
    write_run_state(w, r, state);
    write_run_info(w, r, info);
  }
  if (!file.close()) w.fail_hdf5("the file (on closing it)");
}

// Flushes the file's data to the disk, so that the rename publishes a complete file.
bool sync_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

void write_mpm_checkpoint(const fs::path& file, const mpm::MpmState& solver,
                          const MpmCheckpointInfo& info) {
  const fs::path tmp = temporary_path_for(file);
  const QuietHdf5Errors quiet;
  try {
    const Writer writer(tmp.string());
    write_checkpoint_file(writer, solver, info);
    if (!sync_file(tmp)) writer.fail(fmt::format("cannot sync it: {}", std::strerror(errno)));
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write checkpoint {}: cannot rename {} to it: {}", file.string(),
                            tmp.string(), ec.message()));
  }
}

}  // namespace pilempm
