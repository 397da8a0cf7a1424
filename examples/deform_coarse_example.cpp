// Moves the embedded example's sphere template with the RBF through the user's pairs only (the
// coarse level) and writes it; prints how far the paired vertices moved.
//   deform_coarse_example [template curves pairs output.off]
#include <meshfit/deform.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include <iostream>

int main(int argc, char** argv) {
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string template_path = argc > 1 ? argv[1] : dir + "/template.off";
  const std::string curves_path = argc > 2 ? argv[2] : dir + "/curves.polylines.txt";
  const std::string pairs_path = argc > 3 ? argv[3] : dir + "/pairs.txt";
  const std::string output_path = argc > 4 ? argv[4] : "deform_coarse_example.off";
  try {
    using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
    Mesh tm;
    meshfit::read_triangle_mesh(template_path, tm);
    const auto network = meshfit::read_curve_network(curves_path);
    const auto pairs = meshfit::read_correspondences(pairs_path, network);
    const meshfit::Deformation_report r =
        meshfit::deform_coarse(tm, network, pairs, meshfit::parameters::rbf_kernel(meshfit::Rbf_kernel::linear));
    std::cout << "coarse RBF through " << r.user_pairs << " pairs (" << r.coarse_fit.auxiliary_pairs
              << " auxiliary), residual " << r.coarse_fit.relative_residual << ", " << r.coarse_seconds << " s\n";
    for (const auto& c : pairs)
      std::cout << "  template vertex " << c.template_vertex << " now at "
                << tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(c.template_vertex))) << "\n";
    meshfit::write_triangle_mesh(output_path, tm);
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
