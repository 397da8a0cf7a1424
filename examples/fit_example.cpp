// The whole pipeline on the embedded example: the sphere template is deformed onto the curve
// network, partitioned by the curves and smoothed, in one call; the result is verified and
// written with its regions and curve edges. Prints what each stage did.
//   fit_example [template curves pairs output.ply]
#include <meshfit/fit.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include <iostream>

int main(int argc, char** argv) {
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string template_path = argc > 1 ? argv[1] : dir + "/template.off";
  const std::string curves_path = argc > 2 ? argv[2] : dir + "/curves.polylines.txt";
  const std::string pairs_path = argc > 3 ? argv[3] : dir + "/pairs.txt";
  const std::string output_path = argc > 4 ? argv[4] : "fit_example.ply";
  try {
    Mesh tm;
    meshfit::read_triangle_mesh(template_path, tm);
    const auto network = meshfit::read_curve_network(curves_path);
    const auto pairs = meshfit::read_correspondences(pairs_path, network);
    auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
    auto region = tm.add_property_map<Mesh::Face_index, int>("f:region", 0).first;
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(
        tm, network, pairs, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
    const auto& d = r.deformation;
    const auto& p = r.partition;
    const auto& s = r.smoothing;
    std::cout << "template: " << r.template_vertices << " vertices, " << r.template_faces << " faces; network: "
              << network.number_of_vertices() << " vertices, " << network.number_of_segments() << " segments\n"
              << "deform:    " << d.fine_pairs << " pairs, " << d.flips_found << " flips found and fixed in "
              << d.flip_rounds << " rounds, " << d.vertices_inserted_for_density + d.vertices_inserted_for_flips
              << " vertices inserted, " << r.deform_seconds * 1e3 << " ms\n"
              << "partition: " << p.existing_edges << " segments already edges, " << p.by_walk << " by walk, "
              << p.by_fallback << " by fallback, " << p.not_embedded.size() << " not embedded; " << p.regions
              << " regions, " << r.partition_seconds * 1e3 << " ms\n"
              << "smooth:    " << s.iterations << " iterations, " << s.fixed_vertices << " vertices fixed, mean move "
              << s.mean_displacement << ", " << r.smooth_seconds * 1e3 << " ms\n"
              << "result:    " << r.vertices << " vertices, " << r.faces << " faces, smallest angle "
              << r.minimum_angle_deg << " degrees, verification "
              << (r.verification.passed() ? "passed" : "FAILED") << "\n";
    for (const std::string& problem : r.verification.problems()) std::cout << "  problem: " << problem << "\n";
    meshfit::write_triangle_mesh(output_path, tm,
                                 CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
    std::cout << "wrote " << output_path << "\n";
    return r.verification.passed() ? 0 : 3;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  } catch (const meshfit::Algorithm_failure& e) {
    std::cerr << "failed: " << e.what() << "\n";
    return 3;
  }
}
