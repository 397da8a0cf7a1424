// Reads a template into a CGAL::Surface_mesh, a curve network and correspondences, checks them
// against each other and writes the template back out as OBJ with one region and no curve edges.
//   io_example [template.off curves.polylines.txt pairs.txt output.obj]
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include <iostream>

int main(int argc, char** argv) {
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string template_path = argc > 1 ? argv[1] : dir + "/template.off";
  const std::string curves_path = argc > 2 ? argv[2] : dir + "/curves.polylines.txt";
  const std::string pairs_path = argc > 3 ? argv[3] : dir + "/pairs.txt";
  const std::string output_path = argc > 4 ? argv[4] : "io_example_output.obj";

  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  try {
    Mesh tm;
    const meshfit::Mesh_read_report report = meshfit::read_triangle_mesh(template_path, tm);
    const meshfit::Curve_network network = meshfit::read_curve_network(curves_path);
    const auto pairs = meshfit::read_correspondences(pairs_path, network);
    meshfit::validate_correspondences(pairs, meshfit::to_mesh_data(tm).points, network);

    std::cout << template_path << ": " << tm.number_of_vertices() << " vertices, "
              << tm.number_of_faces() << " faces, " << report.degenerate_faces.size()
              << " degenerate\n"
              << curves_path << ": " << network.number_of_vertices() << " network vertices, "
              << network.number_of_segments() << " segments, " << network.feature_points().size()
              << " feature points\n"
              << pairs_path << ": " << pairs.size() << " pairs\n";

    auto patch = tm.add_property_map<Mesh::Face_index, int>("f:patch", 0).first;
    meshfit::Write_options options;
    options.protected_paths = {template_path};  // never overwrite the input
    meshfit::write_triangle_mesh(output_path, tm, CGAL::parameters::face_patch_map(patch), options);
    std::cout << "wrote " << output_path << "\n";
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
