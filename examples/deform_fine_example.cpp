// Deforms the embedded example's sphere template onto its curve network (coarse, then the default
// `surface` fine level: curves embedded in the coarse surface, then moved into place) and
// writes the result; prints what the deformation did.
//   deform_fine_example [template curves pairs output.off]
#include <meshfit/deform.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include <iostream>

int main(int argc, char** argv) {
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string template_path = argc > 1 ? argv[1] : dir + "/template.off";
  const std::string curves_path = argc > 2 ? argv[2] : dir + "/curves.polylines.txt";
  const std::string pairs_path = argc > 3 ? argv[3] : dir + "/pairs.txt";
  const std::string output_path = argc > 4 ? argv[4] : "deform_fine_example.off";
  try {
    CGAL::Surface_mesh<meshfit::Point_3> tm;
    meshfit::read_triangle_mesh(template_path, tm);
    const auto network = meshfit::read_curve_network(curves_path);
    const auto pairs = meshfit::read_correspondences(pairs_path, network);
    const meshfit::Deformation_report r = meshfit::deform_template(tm, network, pairs);
    std::cout << "coarse: " << r.user_pairs << " pairs, " << r.coarse_seconds << " s\n"
              << "fine: " << r.fine_pairs << " pairs, " << r.flip_rounds << " rounds, " << r.flips_found
              << " flips found, " << r.faces_subdivided << " faces subdivided, " << r.remaining_flips
              << " remaining, " << r.vertices_inserted_for_density << " vertices inserted for density, "
              << r.fine_seconds << " s\n"
              << "fine level " << meshfit::to_string(r.fine_level) << ": " << r.segments_embedded
              << " segments embedded as edge chains on the coarse surface (" << r.segments_by_shortest_path
              << " by shortest path), " << r.remaining_folds << " faces still beside a fold\n"
              << "result: " << r.vertices << " vertices, " << r.faces << " faces\n";
    meshfit::write_triangle_mesh(output_path, tm);
    return r.remaining_flips == 0 && r.remaining_folds == 0 ? 0 : 3;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "invalid input: " << e.what() << "\n";
    return 1;
  } catch (const meshfit::Algorithm_failure& e) {
    std::cerr << "cannot fit: " << e.what() << "\n";
    return 3;
  }
}
