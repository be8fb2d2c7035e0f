// The background grid (uniform and graded axes, cell lookup, boundary conditions) and the shape
// functions: partition of unity, zero sum of gradients, exact reproduction of a linear field and
// of its gradient, continuity across cell boundaries, and GIMP against a numerical integral.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "../support/mpm_builders.hpp"
#include "pilempm/core/error.hpp"
#include "pilempm/mpm/grid.hpp"
#include "pilempm/mpm/particles.hpp"
#include "pilempm/mpm/shape_functions.hpp"

namespace pilempm::mpm {
namespace {

GridAxis graded_axis() {
  return GridAxis::graded(0.0, 1.0, 0.2, 0.46, 0.02, 1.3);
}

TEST(GridAxis, UniformAxisHasEqualCells) {
  const GridAxis axis = GridAxis::uniform(-1.0, 2.0, 6);
  EXPECT_EQ(axis.node_count(), 7);
  EXPECT_TRUE(axis.is_uniform());
  EXPECT_DOUBLE_EQ(axis.min_spacing(), 0.5);
  EXPECT_EQ(axis.cell_of(-1.0), 0);
  EXPECT_EQ(axis.cell_of(-0.5), 1);  // a node belongs to the cell on its right
  EXPECT_EQ(axis.cell_of(-0.5000001), 0);
  EXPECT_EQ(axis.cell_of(2.0), 5);   // the end node belongs to the last cell
  EXPECT_EQ(axis.cell_of(-5.0), 0);  // clamped outside
  EXPECT_EQ(axis.cell_of(9.0), 5);
}

TEST(GridAxis, RejectsBadCoordinates) {
  EXPECT_THROW(GridAxis({0.0}), InvalidValue);
  EXPECT_THROW(GridAxis({0.0, 1.0, 1.0}), InvalidValue);
  EXPECT_THROW(GridAxis({0.0, 2.0, 1.0}), InvalidValue);
  EXPECT_THROW(GridAxis::uniform(0.0, 1.0, 0), InvalidValue);
  EXPECT_THROW(GridAxis::graded(0.0, 1.0, 0.5, 1.5, 0.1, 1.2), InvalidValue);
  EXPECT_THROW(GridAxis::graded(0.0, 1.0, 0.2, 0.4, 0.1, 0.9), InvalidValue);
}

TEST(GridAxis, GradedAxisIsFineInTheBandAndGrowsOutside) {
  const GridAxis axis = graded_axis();
  EXPECT_FALSE(axis.is_uniform());
  EXPECT_DOUBLE_EQ(axis.start(), 0.0);
  EXPECT_DOUBLE_EQ(axis.end(), 1.0);
  int band_cells = 0;
  for (int c = 0; c < axis.cell_count(); ++c) {
    const double middle = 0.5 * (axis.node(c) + axis.node(c + 1));
    if (middle > 0.2 && middle < 0.46) {
      EXPECT_NEAR(axis.spacing(c), 0.02, 1e-12);
      ++band_cells;
    }
    if (c > 0) {  // neighbouring cells differ at most by the growth ratio (within the scaling)
      const double ratio = axis.spacing(c) / axis.spacing(c - 1);
      EXPECT_LT(std::max(ratio, 1.0 / ratio), 1.3 * 1.5) << c;
    }
  }
  EXPECT_EQ(band_cells, 13);
  EXPECT_GT(axis.spacing(axis.cell_count() - 1), 0.05);
  // Binary search agrees with a linear scan.
  for (double x = -0.1; x <= 1.1; x += 0.0137) {
    int expected = 0;
    while (expected + 1 < axis.cell_count() && x >= axis.node(expected + 1)) ++expected;
    EXPECT_EQ(axis.cell_of(x), expected) << x;
  }
  const GridAxis capped = GridAxis::graded(0.0, 10.0, 0.0, 1.0, 0.1, 2.0, 0.5);
  for (int c = 0; c < capped.cell_count(); ++c) EXPECT_LE(capped.spacing(c), 0.5 * 1.5);
}

TEST(Grid, BoundaryConditionsConstrainTheSideNodes) {
  Grid grid(GridAxis::uniform(0.0, 3.0, 3), GridAxis::uniform(0.0, 2.0, 2));
  EXPECT_EQ(grid.node_count(), 12);
  EXPECT_EQ(grid.node_index(2, 1), 6);
  grid.set_boundary(Side::bottom, BoundaryCondition::fixed);
  grid.set_boundary(Side::right, BoundaryCondition::roller);
  grid.set_axis_of_symmetry(true);
  std::vector<double> vx(12, 1.0), vy(12, 1.0);
  grid.apply_boundary_conditions(vx.data(), vy.data());
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 4; ++i) {
      const int n = grid.node_index(i, j);
      const bool bottom = j == 0, left = i == 0, right = i == 3;
      EXPECT_EQ(vx[n], bottom || left || right ? 0.0 : 1.0) << i << "," << j;
      EXPECT_EQ(vy[n], bottom ? 0.0 : 1.0) << i << "," << j;
    }
  }
  Grid shifted(GridAxis::uniform(0.5, 3.0, 3), GridAxis::uniform(0.0, 2.0, 2));
  EXPECT_THROW(shifted.set_axis_of_symmetry(true), InvalidValue);
}

// Checks the 1D weights of one particle; returns them densely over all nodes.
std::vector<double> dense(const GridAxis& axis, const AxisWeights& w, bool gradient) {
  std::vector<double> out(axis.node_count(), 0.0);
  for (int k = 0; k < w.count; ++k) out[w.first + k] = gradient ? w.gradient[k] : w.weight[k];
  return out;
}

void expect_consistent(const GridAxis& axis, const AxisWeights& w, double x, const char* label) {
  ASSERT_GE(w.first, 0) << label;
  ASSERT_LE(w.first + w.count, axis.node_count()) << label;
  ASSERT_LE(w.count, AxisWeights::kMaxNodes) << label;
  double sum = 0.0, gradient_sum = 0.0, moment = 0.0, gradient_moment = 0.0;
  for (int k = 0; k < w.count; ++k) {
    EXPECT_GE(w.weight[k], -1e-15) << label << " x=" << x;
    sum += w.weight[k];
    gradient_sum += w.gradient[k];
    moment += w.weight[k] * axis.node(w.first + k);
    gradient_moment += w.gradient[k] * axis.node(w.first + k);
  }
  const double h = axis.spacing(axis.cell_of(x));
  EXPECT_NEAR(sum, 1.0, 1e-14) << label << " x=" << x;
  EXPECT_NEAR(gradient_sum * h, 0.0, 1e-12) << label << " x=" << x;
  EXPECT_NEAR(moment, x, 1e-14) << label << " x=" << x;             // Σ S_i x_i = x_p
  EXPECT_NEAR(gradient_moment, 1.0, 1e-11) << label << " x=" << x;  // Σ dS_i/dx x_i = 1
}

TEST(ShapeFunctions, PartitionOfUnityAndLinearReproduction) {
  const GridAxis uniform = GridAxis::uniform(0.0, 1.0, 10);
  const GridAxis graded = graded_axis();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(0.0, 1.0);
  for (const GridAxis* axis : {&uniform, &graded}) {
    for (int trial = 0; trial < 2000; ++trial) {
      const double x = position(rng);
      const double h = axis->spacing(axis->cell_of(x));
      AxisWeights w;
      linear_weights(*axis, x, w);
      expect_consistent(*axis, w, x, "linear");
      for (double fraction : {0.1, 0.25, 0.5}) {  // 1/(2 n) for n = 5, 2, 1 particles per cell
        gimp_weights(*axis, x, fraction * h, w);
        expect_consistent(*axis, w, x, "gimp");
      }
    }
    // Exactly on nodes and at the ends.
    for (int i = 0; i < axis->node_count(); ++i) {
      AxisWeights w;
      gimp_weights(*axis, axis->node(i), 0.25 * axis->min_spacing(), w);
      expect_consistent(*axis, w, axis->node(i), "gimp at a node");
    }
  }
}

TEST(ShapeFunctions, GimpMatchesTheAveragedHatFunction) {
  // S_i = 1/(2l) ∫ N_i over the domain, by a fine midpoint rule, on the graded axis.
  const GridAxis axis = graded_axis();
  auto hat = [&](int i, double x) {
    if (i > 0 && x >= axis.node(i - 1) && x <= axis.node(i))
      return (x - axis.node(i - 1)) / axis.spacing(i - 1);
    if (i + 1 < axis.node_count() && x >= axis.node(i) && x <= axis.node(i + 1))
      return (axis.node(i + 1) - x) / axis.spacing(i);
    return 0.0;
  };
  for (double x : {0.1234, 0.1999, 0.2003, 0.4471, 0.462, 0.6, 0.8}) {  // domains inside the grid
    const double l = 0.3 * axis.spacing(axis.cell_of(x));
    AxisWeights w;
    gimp_weights(axis, x, l, w);
    const std::vector<double> weights = dense(axis, w, false);
    const std::vector<double> gradients = dense(axis, w, true);
    for (int i = 0; i < axis.node_count(); ++i) {
      const int samples = 20000;
      double integral = 0.0;
      for (int k = 0; k < samples; ++k) integral += hat(i, x - l + (k + 0.5) * 2.0 * l / samples);
      EXPECT_NEAR(weights[i], integral / samples, 1e-8) << "node " << i << " x=" << x;
      EXPECT_NEAR(gradients[i], (hat(i, x + l) - hat(i, x - l)) / (2.0 * l), 1e-10)
          << "node " << i << " x=" << x;
    }
  }
}

TEST(ShapeFunctions, GimpWeightsAreContinuousAcrossCellBoundaries) {
  const GridAxis uniform = GridAxis::uniform(0.0, 1.0, 10);
  const GridAxis graded = graded_axis();
  for (const GridAxis* axis : {&uniform, &graded}) {
    for (int i = 2; i + 2 < axis->node_count(); ++i) {
      const double node = axis->node(i);
      const double l = 0.25 * std::min(axis->spacing(i - 1), axis->spacing(i));
      const double eps = 1e-9 * axis->spacing(i);
      // The node itself, and the points where the domain's ends cross the node.
      for (double x : {node, node - l, node + l}) {
        AxisWeights before, after;
        gimp_weights(*axis, x - eps, l, before);
        gimp_weights(*axis, x + eps, l, after);
        const std::vector<double> a = dense(*axis, before, false), b = dense(*axis, after, false);
        for (int k = 0; k < axis->node_count(); ++k)
          EXPECT_NEAR(a[k], b[k], 1e-8) << "node " << k << " x=" << x;
        // The GIMP gradient is continuous too (it is the difference of two hat values).
        const std::vector<double> ga = dense(*axis, before, true), gb = dense(*axis, after, true);
        for (int k = 0; k < axis->node_count(); ++k)
          EXPECT_NEAR(ga[k] * axis->spacing(i), gb[k] * axis->spacing(i), 1e-6)
              << "gradient, node " << k << " x=" << x;
      }
    }
  }
}

TEST(ShapeFunctions, GimpDomainIsKeptInsideTheGrid) {
  // A particle domain reaching past the end of the axis is shrunk symmetrically: the weights
  // still sum to one and reproduce x.
  const GridAxis axis = GridAxis::uniform(0.0, 1.0, 4);
  for (double x : {0.0, 0.01, 0.1, 0.99, 1.0}) {
    AxisWeights w;
    gimp_weights(axis, x, 0.125, w);
    expect_consistent(axis, w, x, "near the end");
  }
}

TEST(ShapeFunctions, TwoDimensionalStencilIsATensorProduct) {
  Grid grid(GridAxis::uniform(0.0, 1.0, 8), graded_axis());
  Stencil stencil;
  compute_stencil(grid, ShapeFunction::cpgimp, 0.31, 0.43, 0.03, 0.004, stencil);
  double sum = 0.0, gx = 0.0, gy = 0.0, mx = 0.0, my = 0.0;
  for (int j = 0; j < stencil.y.count; ++j) {
    for (int i = 0; i < stencil.x.count; ++i) {
      const double s = stencil.x.weight[i] * stencil.y.weight[j];
      sum += s;
      gx += stencil.x.gradient[i] * stencil.y.weight[j];
      gy += stencil.x.weight[i] * stencil.y.gradient[j];
      mx += s * grid.x_axis().node(stencil.x.first + i);
      my += s * grid.y_axis().node(stencil.y.first + j);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_NEAR(gx, 0.0, 1e-11);
  EXPECT_NEAR(gy, 0.0, 1e-10);
  EXPECT_NEAR(mx, 0.31, 1e-14);
  EXPECT_NEAR(my, 0.43, 1e-14);
}

TEST(Particles, FillRectangleGivesVolumeMassAndSizes) {
  const Grid grid(GridAxis::uniform(0.0, 2.0, 4), GridAxis::uniform(0.0, 1.0, 2));
  Particles plane, axisymmetric;
  RectangleFill fill = test_support::block_fill(0.0, 1.0, 0.0, 1.0, 2000.0);
  EXPECT_EQ(fill_rectangle(plane, grid, Geometry::plane_strain, fill), 2u * 2u * 4u);
  EXPECT_EQ(fill_rectangle(axisymmetric, grid, Geometry::axisymmetric, fill), 16u);
  double area = 0.0, volume = 0.0, mass = 0.0;
  for (std::size_t p = 0; p < plane.size(); ++p) {
    area += plane.volume[p];
    volume += axisymmetric.volume[p];
    mass += axisymmetric.mass[p];
    EXPECT_DOUBLE_EQ(plane.half_size[p].x(), 0.125);
    EXPECT_DOUBLE_EQ(plane.half_size[p].y(), 0.125);
  }
  EXPECT_NEAR(area, 1.0, 1e-14);
  EXPECT_NEAR(volume, 0.5, 1e-14);  // ∫ r dA over [0,1]^2, per radian: exact for the midpoint rule
  EXPECT_NEAR(mass, 1000.0, 1e-10);
  EXPECT_LT(Particles::bytes_per_particle(), 1024u);
  fill.x_max = 3.0;
  EXPECT_THROW(fill_rectangle(plane, grid, Geometry::plane_strain, fill), InvalidValue);
}

// limit_volume_ratio: the volume ratio J = det F (· λ_θ in axisymmetry) brought down to the
// limit by an isotropic scaling, the shape F / J^(1/3) (plane strain: F / J^(1/2)) kept; a J at
// or below the limit, or a compressed particle, untouched.
TEST(Particles, LimitVolumeRatioScalesToTheLimitAndKeepsTheShape) {
  Mat2 sheared;
  sheared << 30.0, 12.0, -4.0, 20.0;  // J = 648 in plane strain
  for (const bool axisymmetric : {false, true}) {
    Mat2 f = sheared;
    double hoop = axisymmetric ? 1.8 : 1.0;
    const double j0 = f.determinant() * hoop;
    const double dimensions = axisymmetric ? 3.0 : 2.0;
    const Mat2 shape = sheared / std::pow(j0, 1.0 / dimensions);
    ASSERT_TRUE(limit_volume_ratio(f, hoop, 1.5, axisymmetric));
    EXPECT_NEAR(f.determinant() * hoop, 1.5, 1e-12);
    EXPECT_LT((f / std::pow(1.5, 1.0 / dimensions) - shape).norm(), 1e-12);
    if (!axisymmetric) {
      EXPECT_EQ(hoop, 1.0);  // plane strain keeps F_33 = 1
    }
    // At the limit and below it nothing changes.
    const Mat2 at_limit = f;
    EXPECT_FALSE(limit_volume_ratio(f, hoop, 1.5, axisymmetric));
    EXPECT_EQ(f, at_limit);
    Mat2 compressed = 0.5 * Mat2::Identity();
    double one = 1.0;
    EXPECT_FALSE(limit_volume_ratio(compressed, one, 1.5, axisymmetric));
    EXPECT_EQ(compressed, Mat2(0.5 * Mat2::Identity()));
  }
}

}  // namespace
}  // namespace pilempm::mpm
