// Partitions the embedded example: deforms the sphere template onto the curve network (stage 1),
// makes every curve segment a chain of mesh edges and labels the regions between the curves
// (stage 2), and writes the mesh with its regions and curve edges; prints what it did.
//   partition_example [template curves pairs output.ply]
#include <meshfit/deform.h>
#include <meshfit/io.h>
#include <meshfit/partition.h>

#include <CGAL/Surface_mesh.h>

#include <iostream>

int main(int argc, char** argv) {
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string template_path = argc > 1 ? argv[1] : dir + "/template.off";
  const std::string curves_path = argc > 2 ? argv[2] : dir + "/curves.polylines.txt";
  const std::string pairs_path = argc > 3 ? argv[3] : dir + "/pairs.txt";
  const std::string output_path = argc > 4 ? argv[4] : "partition_example.ply";
  try {
    Mesh tm;
    meshfit::read_triangle_mesh(template_path, tm);
    const auto network = meshfit::read_curve_network(curves_path);
    const auto pairs = meshfit::read_correspondences(pairs_path, network);
    const meshfit::Deformation_report d = meshfit::deform_template(tm, network, pairs);
    std::cout << "deform: " << d.vertices << " vertices, " << d.faces << " faces, " << d.remaining_flips
              << " flips remaining\n";

    auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
    auto region = tm.add_property_map<Mesh::Face_index, int>("f:region", 0).first;
    const meshfit::Partition_report r = meshfit::partition_mesh(
        tm, network, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
    std::cout << "partition: " << r.segments << " segments: " << r.existing_edges << " already edges, " << r.by_walk
              << " by walk (" << r.faces_crossed << " faces crossed, " << r.edge_flips << " edge flips), "
              << r.by_fallback << " by fallback, " << r.not_embedded.size() << " not embedded\n"
              << "           " << r.curve_edges << " curve edges, " << r.regions << " regions, " << r.vertices
              << " vertices, " << r.faces << " faces, " << r.seconds * 1e3 << " ms\n";
    meshfit::write_triangle_mesh(output_path, tm,
                                 CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
    std::cout << "wrote " << output_path << "\n";
    return r.not_embedded.empty() ? 0 : 3;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  }
}
