// CGAL Polygon_mesh_slicer driver for bench/compare.
//
//   cgal_slicer epick|epeck MESH.stl|MESH.obj LEVELS.txt
//
// LEVELS.txt holds one level (a double) per line. Prints one JSON line:
// load_s (read the binary STL, merge identical points, build the
// Surface_mesh), build_s (the AABB tree of edges the slicer queries),
// slice_s (one Polygon_mesh_slicer call per level; the polylines are kept
// until the next level, then dropped), and counts.
//
// Build: g++ -O2 -std=c++17 -DNDEBUG -DCGAL_NDEBUG cgal_slicer.cpp -o cgal_slicer -lgmp -lmpfr

#include <CGAL/AABB_halfedge_graph_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using Clock = std::chrono::steady_clock;

static double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

template <class K>
int run(const char* mesh_path, const std::vector<double>& levels) {
  using Point = typename K::Point_3;
  using Mesh = CGAL::Surface_mesh<Point>;
  using Primitive = CGAL::AABB_halfedge_graph_segment_primitive<Mesh>;
  using Traits = CGAL::AABB_traits<K, Primitive>;
  using Tree = CGAL::AABB_tree<Traits>;
  using Slicer = CGAL::Polygon_mesh_slicer<Mesh, K>;
  using Polyline = std::vector<Point>;

  auto t = Clock::now();
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> faces;
  {
    std::string path(mesh_path);
    bool obj = path.size() > 4 && path.substr(path.size() - 4) == ".obj";
    std::ifstream in(mesh_path, std::ios::binary);
    bool ok = in && (obj ? CGAL::IO::read_OBJ(in, points, faces)
                         : CGAL::IO::read_STL(in, points, faces,
                                              CGAL::parameters::use_binary_mode(true)));
    if (!ok) {
      std::cerr << "cannot read " << mesh_path << "\n";
      return 4;
    }
  }
  std::vector<Point> kpoints;
  kpoints.reserve(points.size());
  for (const auto& p : points) kpoints.emplace_back(p[0], p[1], p[2]);
  Mesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(kpoints, faces, mesh);
  double load_s = seconds_since(t);
  if (!CGAL::is_closed(mesh) || num_faces(mesh) != faces.size()) {
    std::cerr << "mesh is not a closed polygon mesh\n";
    return 3;
  }

  t = Clock::now();
  Tree tree(edges(mesh).first, edges(mesh).second, mesh);
  tree.build();
  Slicer slicer(mesh, tree, get(CGAL::vertex_point, mesh));
  double build_s = seconds_since(t);

  t = Clock::now();
  std::size_t polylines = 0, vertices = 0;
  for (double z : levels) {
    std::vector<Polyline> out;
    slicer(typename K::Plane_3(0, 0, 1, -z), std::back_inserter(out));
    polylines += out.size();
    for (const auto& p : out) vertices += p.size();
  }
  double slice_s = seconds_since(t);
  std::printf(
      "{\"triangles\": %zu, \"levels\": %zu, \"load_s\": %.6f, \"build_s\": %.6f, "
      "\"slice_s\": %.6f, \"polylines\": %zu, \"points\": %zu}\n",
      static_cast<std::size_t>(num_faces(mesh)), levels.size(), load_s, build_s, slice_s,
      polylines, vertices);
  return 0;
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: cgal_slicer epick|epeck MESH.stl LEVELS.txt\n";
    return 2;
  }
  std::vector<double> levels;
  {
    std::ifstream in(argv[3]);
    double z;
    while (in >> z) levels.push_back(z);
  }
  std::string kernel = argv[1];
  if (kernel == "epick") return run<CGAL::Exact_predicates_inexact_constructions_kernel>(argv[2], levels);
  if (kernel == "epeck") return run<CGAL::Exact_predicates_exact_constructions_kernel>(argv[2], levels);
  std::cerr << "unknown kernel " << kernel << "\n";
  return 2;
}
