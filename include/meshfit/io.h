// meshfit: reading and writing triangle meshes with regions and curve edges.
//
// Readers are strict: every malformed file gives meshfit::Invalid_input naming the file, the line
// (text formats) or byte offset (binary formats) and the problem, and no allocation is sized by a
// count read from the file before the data behind it has been seen. After parsing, the mesh is
// checked: polygons are triangulated, faces need at least three distinct vertices with indices in
// range, every edge has at most two faces, the faces around each vertex form a single fan, and
// faces sharing an edge are consistently oriented. Degenerate (zero-area) faces and isolated
// vertices are reported, not rejected.
//
// Vertex i of the file is vertex i of the result (isolated vertices are kept), so indices in
// correspondence files and in outputs keep their meaning.
#ifndef MESHFIT_IO_H
#define MESHFIT_IO_H

#include <meshfit/exceptions.h>
#include <meshfit/internal/clear_mesh.h>
#include <meshfit/internal/patches_and_curves.h>
#include <meshfit/internal/triangle_corners.h>
#include <meshfit/kernel.h>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/Named_function_parameters.h>
#include <CGAL/Dynamic_property_map.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace meshfit {

/// File formats. `vtp` (VTK XML PolyData) and `vtk` (legacy VTK, an unstructured grid) are output
/// formats only; `ase` (3ds Max ASCII Scene Export, the format the thesis's system read) is an
/// input format only.
enum class Mesh_format { off, obj, ply, stl, vtp, vtk, ase };

/// The format named by the file's extension (`.off`, `.obj`, `.ply`, `.stl`, `.vtp`, `.vtk`,
/// `.ase`, any case).
/// \throws Invalid_input naming the file for any other extension.
Mesh_format mesh_format_of(const std::string& path);
/// The format's name in capitals: "OFF", "OBJ", "PLY", "STL", "VTP", "VTK", "ASE".
const char* to_string(Mesh_format format);
/// The file extension of `format`, without the dot, in lower case (`"ply"`).
const char* extension_of(Mesh_format format);

/// A triangle mesh as files hold it: vertices in file order, triangles as vertex indices, and
/// optionally a region (patch) per triangle and a set of curve edges.
struct Mesh_data {
  std::vector<Point_3> points;                         ///< vertex i is points[i]
  std::vector<std::array<std::size_t, 3>> triangles;   ///< corners as indices into points
  std::vector<int> face_patch;  ///< empty, or one region index per triangle
  std::vector<std::array<std::size_t, 2>> curve_edges;  ///< edges (pairs of vertex indices) on the curves
  /// Empty, or the texture coordinates (u, v) of each vertex (OBJ `vt` used by every corner of the
  /// vertex alike; PLY vertex properties `u v`, `s t`, `texture_u texture_v`, …).
  std::vector<std::array<double, 2>> vertex_uvs;
  /// Empty, or the normal of each vertex (OBJ `vn` used by every corner of the vertex alike; PLY
  /// `nx ny nz`), as the file gives it (not normalised).
  std::vector<std::array<double, 3>> vertex_normals;
  /// Empty, or the colour of each vertex, red, green, blue, alpha in [0, 1] (OBJ `v x y z r g b`;
  /// PLY `red green blue [alpha]`, integers scaled by 1/255, or floats as they are).
  std::vector<std::array<double, 4>> vertex_colors;
};

/// What reading a mesh found besides the mesh itself.
struct Mesh_read_report {
  std::string file;                       ///< the path read, or the name given for a stream
  Mesh_format format = Mesh_format::off;  ///< the format read
  std::size_t polygons_read = 0;          ///< faces as declared in the file
  std::size_t polygons_triangulated = 0;  ///< of those, faces with more than three sides
  std::vector<std::size_t> degenerate_faces;   ///< triangles whose corners are collinear (exact test)
  std::vector<std::size_t> isolated_vertices;  ///< vertices no face uses
  /// Edges the file lists that are not curve edges: a PLY `edge` element without an integer
  /// property `curve` (as CGAL's write_PLY writes every edge), or instances whose `curve` is 0.
  std::size_t unflagged_edges_ignored = 0;
  /// Attributes the file carries that meshfit reads (and checks) but does not keep, each as a
  /// short phrase naming the attribute and how the file spells it, in the order first met:
  /// "texture coordinates (vt)", "vertex normals (nx ny nz)", "vertex colours (COFF)", ….
  std::vector<std::string> dropped_attributes;
};

/// Reads a mesh file in any supported format (chosen by the extension). Curve edges are OBJ `l`
/// lines and PLY `edge` instances (properties `vertex1`, `vertex2`) whose integer property `curve`
/// is nonzero; an `edge` element without a `curve` property lists no curve edge.
///
/// ASE (`.ase`): the triangles of every `*MESH` block directly inside a `*GEOMOBJECT` (its
/// `*MESH_VERTEX_LIST` of `*MESH_VERTEX i x y z` and `*MESH_FACE_LIST` of
/// `*MESH_FACE i: A: a B: b C: c …`), all objects merged in file order: the vertices of an object
/// follow those of the objects before it, and its face indices are offset accordingly. The
/// coordinates are taken as written (3ds Max exports them in world coordinates); materials,
/// mapping, normals and animation are skipped (reported in `dropped_attributes`). Counts must
/// match `*MESH_NUMVERTEX`/`*MESH_NUMFACES`, vertices and faces must be numbered 0, 1, … in order,
/// and face corners must name vertices of their own object.
/// \throws Invalid_input naming the file and line or byte offset for any malformed content.
Mesh_data read_mesh_data(const std::string& path, Mesh_read_report* report = nullptr);
/// Reads from a stream; `name` is used in error messages.
Mesh_data read_mesh_data(std::istream& in, Mesh_format format, const std::string& name,
                         Mesh_read_report* report = nullptr);
/// Parses an in-memory file; `name` is used in error messages.
Mesh_data parse_mesh_data(const std::string& content, Mesh_format format, const std::string& name,
                          Mesh_read_report* report = nullptr);

/// How `.ply` files are written.
enum class Ply_encoding {
  ascii,                ///< text (default)
  binary_little_endian  ///< binary, little-endian
};

/// Options of the writers.
struct Write_options {
  Ply_encoding ply_encoding = Ply_encoding::ascii;  ///< for `.ply` outputs
  /// Paths the output must not be (the inputs): writing refuses with Invalid_input.
  std::vector<std::string> protected_paths;
  /// Curve edges inside `.obj` (`l` lines) and `.ply` (an `edge` element with `vertex1`,
  /// `vertex2` and `int curve` = 1) files too. Off by default: not every reader accepts them
  /// (CGAL's read_polygon_mesh refuses `l`, meshio an `edge` element); write_curve_edges writes
  /// them to a file of their own. `.vtp`/`.vtk` always hold them (as lines flagged `curve` = 1).
  bool curves_in_mesh = false;
  /// For `.obj` files with regions: the name of a material library (write_material_library) that
  /// an `mtllib` line names, each group then taking its region's material (`usemtl region_<k>`),
  /// so that viewers (f3d) show the regions in their colours. Empty (the default): no materials.
  std::string material_library;
};

/// Writes `mesh` in the format of the path's extension. `.obj` groups faces by region
/// (`g region_<k>`); `.ply` writes a face property `int patch_id` (when the mesh has regions) and
/// no empty element; `.vtp` and `.vtk` write the triangles and the curve edges (as lines) with
/// cell data `region` (-1 on lines) and `curve` (1 on lines, 0 on triangles); `.off` and `.stl`
/// write geometry only. Curve edges go into `.obj` and `.ply` only with
/// `Write_options::curves_in_mesh`. The file is written next to its destination under a temporary
/// name and renamed into place, so a failure leaves no partial file.
/// \throws Invalid_input naming the path when it is protected, has an unknown extension, or
///         cannot be written, or when the mesh refers to vertices that do not exist.
void write_mesh_data(const std::string& path, const Mesh_data& mesh,
                     const Write_options& options = Write_options());
/// Writes `mesh` to a stream in `format` (as the path form does, without the atomic rename).
/// \throws Invalid_input for an input-only format (`ase`) or when the mesh refers to vertices
///         that do not exist.
void write_mesh_data(std::ostream& out, Mesh_format format, const Mesh_data& mesh,
                     Ply_encoding ply_encoding = Ply_encoding::ascii);
/// Writes `mesh` to a stream in `format` with `options` (`protected_paths` do not apply).
/// \throws Invalid_input as the form above.
void write_mesh_data(std::ostream& out, Mesh_format format, const Mesh_data& mesh,
                     const Write_options& options);

/// The curve edges of `mesh` as maximal chains of vertex indices: a chain runs between vertices
/// where the number of curve edges is not 2, or is a closed loop (its first vertex repeated at the
/// end). Every curve edge is in exactly one chain; the order is deterministic.
std::vector<std::vector<std::size_t>> curve_edge_chains(const Mesh_data& mesh);
/// Where write_curve_edges puts the curve edges of the mesh output `output`:
/// `<output>.curves.polylines.txt`.
std::string curve_edges_path(const std::string& output);
/// Writes the chains of curve_edge_chains in the curve-network format (`N x1 y1 z1 …`, shortest
/// round-tripping decimals), atomically like write_mesh_data, so that meshfit reads them back as
/// a curve network.
/// \throws Invalid_input as write_mesh_data does.
void write_curve_edges(const std::string& path, const Mesh_data& mesh,
                       const Write_options& options = Write_options());

/// Where the command line puts the material library of the `.obj` output `output`: `<output>.mtl`.
std::string material_library_path(const std::string& output);
/// Writes one material per region of `mesh` (`newmtl region_<k>`, `newmtl unassigned` for -1),
/// whose diffuse colour `Kd` is region_colour(k), atomically like write_mesh_data. Nothing is
/// written for a mesh without regions.
/// \throws Invalid_input as write_mesh_data does.
void write_material_library(const std::string& path, const Mesh_data& mesh,
                            const Write_options& options = Write_options());

/// \throws Invalid_input when `output` names the same file as one of `inputs` (also through
///         links or different spellings of the path).
void check_output_path(const std::string& output, const std::vector<std::string>& inputs);

/// The colour of region `region` in the PLY outputs (face properties `red green blue` beside
/// `patch_id`, which viewers such as f3d show where they ignore `patch_id`): hue `region` × 0.381966
/// (the golden angle, as in `meshfit view`) at saturation 0.65 and lightness 0.58, so neighbouring
/// numbers differ; mid grey for a negative region (a face in no region).
std::array<std::uint8_t, 3> region_colour(int region);

// ---- one mesh per region ------------------------------------------------------------------------

/// One region of a mesh as a mesh of its own (see split_by_region).
struct Region_mesh {
  int region = 0;  ///< the region id (`face_patch` value) of every face
  /// The region's faces, in the order of the full mesh, and the vertices they use, numbered
  /// 0, 1, … in increasing order of their index in the full mesh, with their texture coordinates,
  /// normals and colours when the full mesh has them; `face_patch` holds `region` for every face;
  /// no curve edges.
  Mesh_data mesh;
  std::vector<std::size_t> vertex_in_full;  ///< local vertex i is vertex vertex_in_full[i] of the full mesh
  std::vector<std::size_t> face_in_full;    ///< local face f is face face_in_full[f] of the full mesh
};

/// Splits `mesh` by region: one Region_mesh per distinct value of `face_patch`, in increasing
/// order of the value (a mesh without `face_patch` is one region, 0). Vertices no face uses are
/// in no region. Every face of `mesh` is in exactly one Region_mesh.
/// \throws Invalid_input when `face_patch` has the wrong size or a triangle refers to a missing
///         vertex.
std::vector<Region_mesh> split_by_region(const Mesh_data& mesh);

/// The file name of a region's mesh. For region `region` in `format`: `region_<k>.<ext>`
/// (`region_-1.<ext>` for the faces of no region, id -1).
std::string region_file_name(int region, Mesh_format format);

/// Checks, before any work, that the region meshes of write_region_meshes can go to `dir`. That is,
/// `dir` is an existing writable directory, or does not exist and its parent is an existing writable
/// directory (it is created when writing), and none of `protected_paths` (the inputs and the other
/// outputs) is a file write_region_meshes could write in it (`region_<k>.<ext>`, `regions.json`).
/// \throws Invalid_input naming `dir` otherwise (for example when it exists and is not a
///         directory).
void check_region_directory(const std::string& dir, Mesh_format format,
                            const std::vector<std::string>& protected_paths);

/// Writes each Region_mesh of split_by_region(mesh) to `dir`/region_file_name(k, format) with
/// write_mesh_data (atomically, never over `options.protected_paths`), creating `dir` (not its
/// parents) when it is missing. Returns the regions written, in the order of the files.
/// \throws Invalid_input as check_region_directory and write_mesh_data do.
std::vector<Region_mesh> write_region_meshes(const std::string& dir, const Mesh_data& mesh, Mesh_format format,
                                             const Write_options& options = Write_options());

// ---- TriangleMesh front end ---------------------------------------------------------------------

/// Replaces the content of `tm` by `mesh` and returns the vertex created for each point.
/// \tparam TriangleMesh a model of `MutableFaceGraph`
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param mesh the mesh to build: vertex i of `mesh` becomes the i-th vertex added to `tm`
/// \param tm the mesh to fill (cleared first)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the vertex of `tm` created for each of `mesh.points`, in order
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///                    meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for
///                     `CGAL::vertex_point_t` must be available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{output: receives the region of each face, `mesh.face_patch[f]` for
///                           face f (0 for every face when `mesh.face_patch` is empty)}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an
///                    integer type as value type}
///     \cgalParamDefault{none: the regions are not written}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{output: receives `true` on the curve edges of `mesh`, `false` on every
///                           other edge}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool`
///                    as value type}
///     \cgalParamDefault{none: the curve edges are not written}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input when `mesh` is not a valid oriented 2-manifold (use read_mesh_data, which
///         checks this with line numbers, to read files), when `face_patch` has the wrong size, or
///         when a curve edge is not an edge of the mesh.
template <typename TriangleMesh,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor>
build_triangle_mesh(const Mesh_data& mesh, TriangleMesh& tm,
                    const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using face_descriptor = typename GT::face_descriptor;

  auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                              get_property_map(CGAL::vertex_point, tm));

  if (!mesh.face_patch.empty() && mesh.face_patch.size() != mesh.triangles.size())
    throw Invalid_input("face_patch has " + std::to_string(mesh.face_patch.size()) + " entries for " +
                        std::to_string(mesh.triangles.size()) + " triangles");
  internal::clear_mesh(tm);
  std::vector<vertex_descriptor> vertex_of(mesh.points.size());
  using P = typename boost::property_traits<decltype(vpm)>::value_type;
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    vertex_of[i] = add_vertex(tm);
    const Point_3& p = mesh.points[i];
    put(vpm, vertex_of[i], P(p.x(), p.y(), p.z()));  // any point type with double coordinates
  }
  std::vector<face_descriptor> face_of(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    if (t[0] >= vertex_of.size() || t[1] >= vertex_of.size() || t[2] >= vertex_of.size())
      throw Invalid_input("triangle " + std::to_string(f) + " refers to a missing vertex");
    const std::array<vertex_descriptor, 3> corners{vertex_of[t[0]], vertex_of[t[1]],
                                                   vertex_of[t[2]]};
    face_of[f] = CGAL::Euler::add_face(corners, tm);
    if (face_of[f] == GT::null_face())
      throw Invalid_input("triangle " + std::to_string(f) +
                          " cannot be added: the faces do not form an oriented 2-manifold");
  }

  internal::put_patches_and_curves(mesh, tm, vertex_of, face_of, np);
  return vertex_of;
}

/// Reads a mesh file into `tm` (see read_mesh_data and build_triangle_mesh for what is checked).
/// \tparam TriangleMesh a model of `MutableFaceGraph`
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param path the file, in a format chosen by its extension (mesh_format_of)
/// \param tm the mesh to fill (cleared first): vertex i of the file is its i-th vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what reading found besides the mesh (Mesh_read_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///                    meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for
///                     `CGAL::vertex_point_t` must be available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{output: receives the region of each face as the file gives it (0 for
///                           every face when it gives none)}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an
///                    integer type as value type}
///     \cgalParamDefault{none: the regions are not written}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{output: receives `true` on the file's curve edges, `false` on every
///                           other edge}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool`
///                    as value type}
///     \cgalParamDefault{none: the curve edges are not written}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input naming the file and line or byte offset for any malformed content, and
///         as build_triangle_mesh.
template <typename TriangleMesh,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
Mesh_read_report read_triangle_mesh(const std::string& path, TriangleMesh& tm,
                                    const NamedParameters& np = CGAL::parameters::default_values()) {
  Mesh_read_report report;
  const Mesh_data data = read_mesh_data(path, &report);
  build_triangle_mesh(data, tm, np);
  return report;
}

/// Flattens `tm` into Mesh_data. Vertices are numbered in the order of `vertices(tm)` (for
/// CGAL::Surface_mesh without removed elements: their index).
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the points, triangles and, when the maps are given, regions and curve edges of `tm`
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///                    a point type with `x()`, `y()` and `z()` as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for
///                     `CGAL::vertex_point_t` must be available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{input: the region of each face, copied into `face_patch` (as `int`)}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an
///                    integer type as value type}
///     \cgalParamDefault{none: `face_patch` is left empty}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the edges where it is `true` become `curve_edges`}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool`
///                    as value type}
///     \cgalParamDefault{none: `curve_edges` is left empty}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
template <typename TriangleMesh,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
Mesh_data to_mesh_data(const TriangleMesh& tm,
                       const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;

  auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                              get_const_property_map(CGAL::vertex_point, tm));
  auto index = get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm);

  Mesh_data out;
  out.points.reserve(num_vertices(tm));
  for (auto v : vertices(tm)) {
    put(index, v, out.points.size());
    const auto& p = get(vpm, v);
    out.points.emplace_back(p.x(), p.y(), p.z());
  }
  auto fpm = get_parameter(np, CGAL::internal_np::face_patch);
  constexpr bool has_patches =
      !std::is_same_v<decltype(fpm), CGAL::internal_np::Param_not_found>;
  out.triangles.reserve(num_faces(tm));
  for (auto f : faces(tm)) {
    out.triangles.push_back(internal::triangle_corners(f, tm, index));
    if constexpr (has_patches) out.face_patch.push_back(static_cast<int>(get(fpm, f)));
  }
  auto ecm = get_parameter(np, CGAL::internal_np::edge_is_constrained);
  if constexpr (!std::is_same_v<decltype(ecm), CGAL::internal_np::Param_not_found>) {
    for (auto e : edges(tm))
      if (get(ecm, e))
        out.curve_edges.push_back({get(index, source(e, tm)), get(index, target(e, tm))});
  }
  return out;
}

/// Writes `tm`: write_mesh_data(path, to_mesh_data(tm, np), options) (see write_mesh_data for
/// the formats).
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param path the output, in the format of its extension
/// \param tm the mesh
/// \param np an optional sequence of named parameters among the ones listed below
/// \param options the writers' options (PLY encoding, protected paths, curve edges inside the file)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///                    a point type with `x()`, `y()` and `z()` as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for
///                     `CGAL::vertex_point_t` must be available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{input: the region of each face, written as the format allows (OBJ
///                           groups, PLY `patch_id`, VTK cell data `region`)}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an
///                    integer type as value type}
///     \cgalParamDefault{none: no regions are written}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges, where it is `true` (written to `.vtp` and `.vtk`
///                           files, and to `.obj` and `.ply` files with
///                           `Write_options::curves_in_mesh`)}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///                    `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool`
///                    as value type}
///     \cgalParamDefault{none: no curve edges}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input as write_mesh_data.
template <typename TriangleMesh,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
void write_triangle_mesh(const std::string& path, const TriangleMesh& tm,
                         const NamedParameters& np = CGAL::parameters::default_values(),
                         const Write_options& options = Write_options()) {
  write_mesh_data(path, to_mesh_data(tm, np), options);
}

}  // namespace meshfit

#endif  // MESHFIT_IO_H
