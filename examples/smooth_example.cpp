// Smooths a mesh with the thesis's method (modified mean-curvature flow, then modified Laplacian
// flow) and writes the result; prints what it did. Without arguments: the embedded example's
// template, roughened with seeded noise so that there is something to smooth.
//   smooth_example [mesh output.off]
#include <meshfit/io.h>
#include <meshfit/smooth.h>

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <iostream>
#include <random>

int main(int argc, char** argv) {
  const std::string input_path = argc > 1 ? argv[1] : std::string(MESHFIT_EXAMPLE_DATA_DIR) + "/template.off";
  const std::string output_path = argc > 2 ? argv[2] : "smooth_example.off";
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  try {
    Mesh tm;
    meshfit::read_triangle_mesh(input_path, tm);
    if (argc <= 1) {
      // Move every vertex along its normal by a seeded random amount (a fifth of an edge).
      auto normals = tm.add_property_map<Mesh::Vertex_index, meshfit::Vector_3>("v:normal").first;
      CGAL::Polygon_mesh_processing::compute_vertex_normals(tm, normals);
      std::mt19937 rng(1);
      std::normal_distribution<double> noise(0.0, 0.2 * 0.07);
      for (auto v : tm.vertices()) tm.point(v) = tm.point(v) + noise(rng) * normals[v];
    }
    const double volume = CGAL::Polygon_mesh_processing::volume(tm);
    auto progress = [](const meshfit::Progress_step& s) {
      if (s.index % 20 == 0) std::cout << s.stage << ": " << s.step << " " << s.index + 1 << "/" << s.total << "\n";
    };  // returns nothing: never cancels (return false from a bool callback to cancel)
    const meshfit::Smoothing_report r =
        meshfit::smooth_fitted_mesh(tm, meshfit::parameters::progress(progress).number_of_iterations(100));
    std::cout << "smoothed " << r.vertices << " vertices (" << r.fixed_vertices << " fixed): " << r.mean_curvature_iterations
              << " iterations of modified mean-curvature flow, " << r.laplacian_iterations
              << " of modified Laplacian flow, " << r.seconds << " s\n"
              << "displacement: mean " << r.mean_displacement << ", max " << r.max_displacement << "\n"
              << "volume: " << CGAL::Polygon_mesh_processing::volume(tm) / volume << " of the input's\n"
              << "steps shrunk to keep faces from flipping: " << r.steps_reduced << "\n";
    meshfit::write_triangle_mesh(output_path, tm);
    std::cout << "wrote " << output_path << "\n";
    return 0;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  }
}
