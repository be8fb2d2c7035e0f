#include "pilempm/mpm/particles.hpp"

#include <string>

#include "pilempm/core/error.hpp"

namespace pilempm::mpm {

void Particles::reserve(std::size_t count) {
  position.reserve(count);
  velocity.reserve(count);
  mass.reserve(count);
  initial_volume.reserve(count);
  volume.reserve(count);
  initial_half_size.reserve(count);
  half_size.reserve(count);
  deformation_gradient.reserve(count);
  out_of_plane_stretch.reserve(count);
  material.reserve(count);
  state.reserve(count);
  external_force.reserve(count);
}

std::size_t Particles::add(const ParticleInit& particle) {
  position.push_back(particle.position);
  velocity.push_back(particle.velocity);
  mass.push_back(particle.mass);
  initial_volume.push_back(particle.volume);
  volume.push_back(particle.volume);
  initial_half_size.push_back(particle.half_size);
  half_size.push_back(particle.half_size);
  deformation_gradient.push_back(Mat2::Identity());
  out_of_plane_stretch.push_back(1.0);
  material.push_back(particle.material);
  state.push_back(particle.state);
  external_force.push_back(Vec2::Zero());
  return size() - 1;
}

std::size_t Particles::bytes_per_particle() {
  return 5 * sizeof(Vec2) + sizeof(Mat2) + 4 * sizeof(double) + sizeof(int) + sizeof(MaterialState);
}

std::size_t fill_rectangle(Particles& particles, const Grid& grid, Geometry geometry,
                           const RectangleFill& fill) {
  const std::string where = "particle rectangle";
  if (!(fill.x_max > fill.x_min && fill.y_max > fill.y_min))
    throw InvalidValue(where,
                       format_value(fill.x_min) + ".." + format_value(fill.x_max) + " x " +
                           format_value(fill.y_min) + ".." + format_value(fill.y_max),
                       "non-empty (min < max)");
  if (!(fill.x_min >= grid.x_axis().start() && fill.x_max <= grid.x_axis().end() &&
        fill.y_min >= grid.y_axis().start() && fill.y_max <= grid.y_axis().end()))
    throw InvalidValue(where,
                       format_value(fill.x_min) + ".." + format_value(fill.x_max) + " x " +
                           format_value(fill.y_min) + ".." + format_value(fill.y_max),
                       "inside the grid");
  if (geometry == Geometry::axisymmetric && fill.x_min < 0.0)
    throw InvalidValue("particle rectangle x_min (radius)", format_value(fill.x_min),
                       ">= 0 in axisymmetry");
  if (!(fill.density > 0.0)) throw InvalidValue("density", format_value(fill.density), "> 0");
  if (fill.particles_per_cell_x < 1 || fill.particles_per_cell_y < 1)
    throw InvalidValue("particles per cell",
                       std::to_string(fill.particles_per_cell_x) + " x " +
                           std::to_string(fill.particles_per_cell_y),
                       ">= 1 in each direction");
  if (fill.material < 0) throw InvalidValue("material", std::to_string(fill.material), ">= 0");

  const GridAxis& x_axis = grid.x_axis();
  const GridAxis& y_axis = grid.y_axis();
  const int nx = fill.particles_per_cell_x, ny = fill.particles_per_cell_y;
  std::size_t added = 0;
  for (int cj = y_axis.cell_of(fill.y_min); cj <= y_axis.cell_of(fill.y_max); ++cj) {
    const double sub_y = y_axis.spacing(cj) / ny;
    for (int sj = 0; sj < ny; ++sj) {
      const double y = y_axis.node(cj) + (sj + 0.5) * sub_y;
      if (y < fill.y_min || y >= fill.y_max) continue;
      for (int ci = x_axis.cell_of(fill.x_min); ci <= x_axis.cell_of(fill.x_max); ++ci) {
        const double sub_x = x_axis.spacing(ci) / nx;
        for (int si = 0; si < nx; ++si) {
          const double x = x_axis.node(ci) + (si + 0.5) * sub_x;
          if (x < fill.x_min || x >= fill.x_max) continue;
          ParticleInit particle;
          particle.position = Vec2(x, y);
          particle.velocity = fill.initial_velocity;
          const double area = sub_x * sub_y;
          particle.volume = geometry == Geometry::axisymmetric ? x * area : area;
          particle.mass = fill.density * particle.volume;
          particle.half_size = Vec2(0.5 * sub_x, 0.5 * sub_y);
          particle.material = fill.material;
          particle.state = fill.initial_state;
          particles.add(particle);
          ++added;
        }
      }
    }
  }
  return added;
}

}  // namespace pilempm::mpm
