//! Input: a triangle mesh (double coordinates, taken exactly; uint32 index
//! triples) and an exact rational level c as two decimal strings.
//! Output: through the C API of oracle.h, an exact weak-Morse
//! classification of the plane z = c (vertex signs, faces in the plane
//! with their facing, in-plane edge classes, extremal vertices, S_O branch
//! counts) and the polylines of CGAL::Polygon_mesh_slicer with exact
//! rational coordinates.
//!
//! Everything is computed with CGAL's Epeck kernel (exact predicates and
//! exact constructions); the kernel's exactness is asserted at compile
//! time. The classification is derived from SPEC.md section 3 on CGAL's
//! own halfedge structure (CGAL::Surface_mesh), independently of the Rust
//! implementation it checks.
//!
//! What CGAL 5.5's Polygon_mesh_slicer returns (read from
//! CGAL/Polygon_mesh_slicer.h, Polygon_mesh_slicer/Traversal_traits.h,
//! Axis_parallel_plane_traits.h and boost/graph/split_graph_into_polylines.h):
//! - The plane (0, 0, 1, -c) is recognised as axis-parallel; sides are
//!   decided by exact comparison of z with c, crossings are computed as
//!   src + (tgt - src) * (c - z_src) / (z_tgt - z_src), exact with Epeck.
//! - Nodes of its graph: every edge crossed strictly (ends on opposite
//!   strict sides), and every on-plane vertex that ends an edge whose other
//!   end is off the plane, or ends a kept coplanar edge (below).
//! - Coplanar edges (both ends on the plane) are kept unless both of their
//!   faces lie in the plane: interior edges of F are dropped; ridges,
//!   valleys, transversal edges and every boundary edge of F (S_O or not)
//!   are kept, each once, as one graph edge between its two vertices.
//! - A face with two crossed edges links their two crossing nodes. A face
//!   with one crossed edge (its third vertex on the plane) links that
//!   crossing to the vertex. Faces touching the plane at one vertex or
//!   along one edge add nothing of their own.
//! - The graph is split into polylines at nodes of degree != 2; cycles
//!   come out closed (first point repeated). An on-plane vertex with no
//!   graph edge (all neighbours strictly on one side: an extremum of P)
//!   comes out as a polyline of one point.
//! So the polylines mix S_O, S_NO, the whole of dF (a boundary edge shared
//! by S_O and dF appears once) and P; interior edges of F never appear.
//! Orientation is CGAL's own (its do_reverse_polyline) and is not compared.

#include "oracle.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Algebraic_structure_traits.h>
#include <CGAL/Gmpq.h>
#include <boost/multiprecision/gmp.hpp>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <iterator>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using Point_2 = Kernel::Point_2;
using Point_3 = Kernel::Point_3;
using Plane_3 = Kernel::Plane_3;
using Mesh = CGAL::Surface_mesh<Point_3>;
using VI = Mesh::Vertex_index;
using HI = Mesh::Halfedge_index;
using FI = Mesh::Face_index;
using EI = Mesh::Edge_index;
using ExactFT = std::decay_t<decltype(CGAL::exact(std::declval<FT>()))>;

// An older CGAL test once used the inexact kernel by mistake: make that a
// compile error here.
static_assert(Kernel::Has_filtered_predicates,
              "the oracle needs a kernel with filtered (exact) predicates");
static_assert(std::is_same<CGAL::Algebraic_structure_traits<FT>::Is_exact,
                           CGAL::Tag_true>::value,
              "the oracle's number type must be exact");
static_assert(std::is_same<CGAL::Algebraic_structure_traits<FT>::Algebraic_category,
                           CGAL::Field_tag>::value ||
                  std::is_base_of<CGAL::Field_tag,
                                  CGAL::Algebraic_structure_traits<FT>::Algebraic_category>::value,
              "the oracle's number type must be a field (exact divisions)");
static_assert(std::is_same<ExactFT, CGAL::Gmpq>::value ||
                  std::is_same<ExactFT, boost::multiprecision::mpq_rational>::value,
              "Epeck's exact number type is expected to be a GMP rational");
static_assert(!std::is_floating_point<FT>::value, "FT must not be a float");

// Error carrying a WMO_ERR_* code.
struct OracleError : std::runtime_error {
  int code;
  OracleError(int c, const std::string& what) : std::runtime_error(what), code(c) {}
};

// Storage behind a wmo_result.
struct Storage {
  std::vector<int8_t> vertex_sign;
  std::vector<uint8_t> vertex_extremum;
  std::vector<uint32_t> vertex_branches;
  std::vector<uint8_t> face_in_plane;
  std::vector<uint32_t> edge_vertices;
  std::vector<uint8_t> edge_class;
  std::vector<size_t> polyline_start;
  std::vector<std::string> text;  // 2 per point: x then y
  std::vector<const char*> point_x;
  std::vector<const char*> point_y;
};

bool is_decimal_integer(const char* s) {
  if (s == nullptr) return false;
  const char* p = s;
  if (*p == '-' || *p == '+') ++p;
  if (*p == '\0') return false;
  for (; *p != '\0'; ++p) {
    if (*p < '0' || *p > '9') return false;
  }
  return true;
}

CGAL::Gmpz parse_integer(const char* s) {
  // Gmpz accepts no leading '+'.
  const char* p = (*s == '+') ? s + 1 : s;
  return CGAL::Gmpz(std::string(p), 10);
}

// The raw GMP rational of Epeck's exact number type (CGAL::Gmpq or Boost's
// GMP-backed mpq_rational, depending on how CGAL was configured).
[[maybe_unused]] mpq_srcptr raw_mpq(const CGAL::Gmpq& q) { return q.mpq(); }
[[maybe_unused]] mpq_srcptr raw_mpq(const boost::multiprecision::mpq_rational& q) { return q.backend().data(); }

// An exact Epeck number from a Gmpq (copies the GMP rational).
FT ft_from_gmpq(const CGAL::Gmpq& q) { return FT(ExactFT(q.mpq())); }

// Exact text "p/q" (or "p" when q = 1), lowest terms, q > 0.
std::string exact_text(const FT& v) {
  const CGAL::Gmpq q(raw_mpq(CGAL::exact(v)));  // GMP keeps it canonical
  std::ostringstream os;
  os << q.numerator();
  if (q.denominator() != 1) os << "/" << q.denominator();
  return os.str();
}

int8_t sign_of(const FT& z, const FT& c) {
  switch (CGAL::compare(z, c)) {
    case CGAL::SMALLER:
      return WMO_BELOW;
    case CGAL::LARGER:
      return WMO_ABOVE;
    default:
      return WMO_ON;
  }
}

// Builds CGAL's halfedge mesh of the input, vertex i and face f being
// input vertex i and face f (checked), every coordinate exact (FT(double)
// is exact: every finite double is a dyadic rational). Throws OracleError
// for an input that is not a closed, oriented 2-manifold.
void build_mesh(const double* xyz, size_t nv, const uint32_t* faces, size_t nf,
                std::vector<Point_3>& points, Mesh& mesh) {
  if (nv > 0 && xyz == nullptr) throw OracleError(WMO_ERR_INPUT, "null vertex array");
  if (nf > 0 && faces == nullptr) throw OracleError(WMO_ERR_INPUT, "null face array");
  if (nv > 0xffffffffu) throw OracleError(WMO_ERR_INPUT, "too many vertices for uint32 ids");
  // Vertices: every finite double is an exact dyadic rational; FT(double)
  // is exact.
  points.reserve(nv);
  for (size_t i = 0; i < nv; ++i) {
    const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw OracleError(WMO_ERR_INPUT, "vertex " + std::to_string(i) + " has a non-finite coordinate");
    points.emplace_back(FT(x), FT(y), FT(z));
  }
  std::vector<std::array<size_t, 3>> polygons(nf);
  for (size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = faces[3 * f + k];
      if (v >= nv)
        throw OracleError(WMO_ERR_INPUT, "face " + std::to_string(f) + " has vertex index " +
                                             std::to_string(v) + " out of range");
      polygons[f][k] = v;
    }
  }
  if (!CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(polygons))
    throw OracleError(WMO_ERR_MESH, "the faces do not form an oriented 2-manifold");

  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (mesh.number_of_vertices() != nv || mesh.number_of_faces() != nf)
    throw OracleError(WMO_ERR_MESH, "the mesh could not be built from the faces");
  // Vertex and face indices follow the input order.
  for (size_t i = 0; i < nv; ++i) {
    if (mesh.point(VI(static_cast<Mesh::size_type>(i))) != points[i])
      throw OracleError(WMO_ERR_INTERNAL, "vertex order not preserved");
  }
  // Face f must be input face f, in the same cyclic order (its halfedge
  // may start at any corner).
  for (size_t f = 0; f < nf; ++f) {
    HI h = mesh.halfedge(FI(static_cast<Mesh::size_type>(f)));
    for (int k = 0; k < 3 && static_cast<size_t>(mesh.source(h)) != polygons[f][0]; ++k)
      h = mesh.next(h);
    for (int k = 0; k < 3; ++k) {
      if (static_cast<size_t>(mesh.source(h)) != polygons[f][k])
        throw OracleError(WMO_ERR_INTERNAL, "face order not preserved");
      h = mesh.next(h);
    }
  }
  for (HI h : mesh.halfedges()) {
    if (mesh.is_border(h)) throw OracleError(WMO_ERR_MESH, "the mesh is not closed");
  }

}

Storage* classify(const double* xyz, size_t nv, const uint32_t* faces, size_t nf,
                  const char* level_num, const char* level_den) {
  if (nv > 0 && xyz == nullptr) throw OracleError(WMO_ERR_INPUT, "null vertex array");
  if (nf > 0 && faces == nullptr) throw OracleError(WMO_ERR_INPUT, "null face array");
  if (nv > 0xffffffffu) throw OracleError(WMO_ERR_INPUT, "too many vertices for uint32 ids");

  // The level, exactly.
  if (!is_decimal_integer(level_num) || !is_decimal_integer(level_den))
    throw OracleError(WMO_ERR_LEVEL, "level numerator/denominator must be decimal integers");
  CGAL::Gmpz num = parse_integer(level_num);
  CGAL::Gmpz den = parse_integer(level_den);
  if (den == 0) throw OracleError(WMO_ERR_LEVEL, "level denominator is zero");
  const FT c = ft_from_gmpq(CGAL::Gmpq(num, den));  // canonicalised

  std::vector<Point_3> points;
  Mesh mesh;
  build_mesh(xyz, nv, faces, nf, points, mesh);

  auto st = std::make_unique<Storage>();

  // Signs s(v) = sign(z - c).
  st->vertex_sign.resize(nv);
  for (size_t i = 0; i < nv; ++i) st->vertex_sign[i] = sign_of(points[i].z(), c);
  auto sgn = [&](VI v) { return st->vertex_sign[static_cast<size_t>(v)]; };

  // Faces in the plane, with the facing of their (x, y) projection.
  st->face_in_plane.assign(nf, WMO_FACE_OFF);
  for (FI f : mesh.faces()) {
    HI h = mesh.halfedge(f);
    VI a = mesh.source(h), b = mesh.target(h), d = mesh.target(mesh.next(h));
    if (sgn(a) != WMO_ON || sgn(b) != WMO_ON || sgn(d) != WMO_ON) continue;
    auto xy = [&](VI v) {
      const Point_3& p = mesh.point(v);
      return Point_2(p.x(), p.y());
    };
    uint8_t facing = WMO_FACE_FLAT;
    switch (CGAL::orientation(xy(a), xy(b), xy(d))) {
      case CGAL::COUNTERCLOCKWISE:
        facing = WMO_FACE_UP;
        break;
      case CGAL::CLOCKWISE:
        facing = WMO_FACE_DOWN;
        break;
      default:
        break;
    }
    st->face_in_plane[static_cast<size_t>(f)] = facing;
  }
  auto in_plane = [&](FI f) { return st->face_in_plane[static_cast<size_t>(f)] != WMO_FACE_OFF; };

  // In-plane edges, each decided once from its two faces.
  st->vertex_branches.assign(nv, 0);
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, uint8_t>> edges;
  for (EI e : mesh.edges()) {
    HI h = mesh.halfedge(e);
    HI g = mesh.opposite(h);
    VI a = mesh.source(h), b = mesh.target(h);
    if (sgn(a) != WMO_ON || sgn(b) != WMO_ON) continue;
    FI fh = mesh.face(h), fg = mesh.face(g);
    VI oh = mesh.target(mesh.next(h)), og = mesh.target(mesh.next(g));
    uint8_t cls;
    if (in_plane(fh) && in_plane(fg)) {
      cls = WMO_EDGE_INTERIOR;
    } else if (in_plane(fh) || in_plane(fg)) {
      const FI flat_face = in_plane(fh) ? fh : fg;
      const VI off_vertex = in_plane(fh) ? og : oh;
      const uint8_t facing = st->face_in_plane[static_cast<size_t>(flat_face)];
      const int8_t other = sgn(off_vertex);  // non-zero: its face is not in F
      const bool so = (facing == WMO_FACE_UP && other == WMO_ABOVE) ||
                      (facing == WMO_FACE_DOWN && other == WMO_BELOW);
      cls = so ? WMO_EDGE_BOUNDARY_SO : WMO_EDGE_BOUNDARY;
    } else {
      const int8_t s1 = sgn(oh), s2 = sgn(og);
      if (s1 == WMO_ON || s2 == WMO_ON)
        throw OracleError(WMO_ERR_INTERNAL, "a face with three on-plane vertices is not in F");
      if (s1 == s2)
        cls = (s1 == WMO_BELOW) ? WMO_EDGE_RIDGE : WMO_EDGE_VALLEY;
      else
        cls = WMO_EDGE_TRANSVERSAL;
    }
    if (cls == WMO_EDGE_TRANSVERSAL || cls == WMO_EDGE_BOUNDARY_SO) {
      st->vertex_branches[static_cast<size_t>(a)] += 1;
      st->vertex_branches[static_cast<size_t>(b)] += 1;
    }
    uint32_t ia = static_cast<uint32_t>(a), ib = static_cast<uint32_t>(b);
    edges.push_back({{std::min(ia, ib), std::max(ia, ib)}, cls});
  }
  std::sort(edges.begin(), edges.end());
  for (const auto& e : edges) {
    st->edge_vertices.push_back(e.first.first);
    st->edge_vertices.push_back(e.first.second);
    st->edge_class.push_back(e.second);
  }

  // Crossed faces with a zero vertex: the other two of opposite signs.
  for (FI f : mesh.faces()) {
    HI h = mesh.halfedge(f);
    for (int k = 0; k < 3; ++k, h = mesh.next(h)) {
      VI z = mesh.source(h), p = mesh.target(h), q = mesh.target(mesh.next(h));
      if (sgn(z) == WMO_ON && sgn(p) != WMO_ON && sgn(q) != WMO_ON && sgn(p) != sgn(q))
        st->vertex_branches[static_cast<size_t>(z)] += 1;
    }
  }

  // Extremal vertices: on the plane, every neighbour strictly above (min)
  // or strictly below (max).
  st->vertex_extremum.assign(nv, WMO_NOT_EXTREMAL);
  for (VI v : mesh.vertices()) {
    if (sgn(v) != WMO_ON || mesh.is_isolated(v)) continue;
    bool all_above = true, all_below = true;
    for (VI n : CGAL::vertices_around_target(mesh.halfedge(v), mesh)) {
      all_above = all_above && sgn(n) == WMO_ABOVE;
      all_below = all_below && sgn(n) == WMO_BELOW;
    }
    if (all_above) st->vertex_extremum[static_cast<size_t>(v)] = WMO_MIN;
    if (all_below) st->vertex_extremum[static_cast<size_t>(v)] = WMO_MAX;
  }

  // CGAL's slicer on the plane z = c.
  std::vector<std::vector<Point_3>> polylines;
  if (nf > 0) {
    CGAL::Polygon_mesh_slicer<Mesh, Kernel> slicer(mesh);
    slicer(Plane_3(FT(0), FT(0), FT(1), -c), std::back_inserter(polylines));
  }
  st->polyline_start.push_back(0);
  for (const auto& pl : polylines) {
    for (const Point_3& p : pl) {
      if (p.z() != c) throw OracleError(WMO_ERR_INTERNAL, "a slicer point is off the plane");
      st->text.push_back(exact_text(p.x()));
      st->text.push_back(exact_text(p.y()));
    }
    st->polyline_start.push_back(st->text.size() / 2);
  }
  for (size_t i = 0; i + 1 < st->text.size(); i += 2) {
    st->point_x.push_back(st->text[i].c_str());
    st->point_y.push_back(st->text[i + 1].c_str());
  }
  return st.release();
}

// Every pair of faces CGAL::Polygon_mesh_processing::self_intersections
// reports (each pair smaller id first, pairs ascending, no repeats), and
// the verdict of does_self_intersect, on the exact mesh.
std::vector<std::pair<uint32_t, uint32_t>> self_intersecting_pairs(
    const double* xyz, size_t nv, const uint32_t* faces, size_t nf, bool& does) {
  std::vector<Point_3> points;
  Mesh mesh;
  build_mesh(xyz, nv, faces, nf, points, mesh);
  namespace PMP = CGAL::Polygon_mesh_processing;
  does = PMP::does_self_intersect(mesh);
  std::vector<std::pair<FI, FI>> found;
  PMP::self_intersections(mesh, std::back_inserter(found));
  std::vector<std::pair<uint32_t, uint32_t>> out;
  out.reserve(found.size());
  for (const auto& fp : found) {
    uint32_t a = static_cast<uint32_t>(static_cast<size_t>(fp.first));
    uint32_t b = static_cast<uint32_t>(static_cast<size_t>(fp.second));
    if (b < a) std::swap(a, b);
    out.emplace_back(a, b);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void write_error(char* err, size_t err_len, const char* msg) {
  if (err == nullptr || err_len == 0) return;
  std::strncpy(err, msg, err_len - 1);
  err[err_len - 1] = '\0';
}

}  // namespace

extern "C" int wmo_classify(const double* xyz, size_t num_vertices, const uint32_t* faces,
                            size_t num_faces, const char* level_num, const char* level_den,
                            wmo_result** result, char* err, size_t err_len) {
  if (result == nullptr) {
    write_error(err, err_len, "result pointer is null");
    return WMO_ERR_INPUT;
  }
  *result = nullptr;
  Storage* st = nullptr;
  try {
    st = classify(xyz, num_vertices, faces, num_faces, level_num, level_den);
    wmo_result* r = new wmo_result();
    r->num_vertices = num_vertices;
    r->vertex_sign = st->vertex_sign.data();
    r->vertex_extremum = st->vertex_extremum.data();
    r->vertex_branches = st->vertex_branches.data();
    r->num_faces = num_faces;
    r->face_in_plane = st->face_in_plane.data();
    r->num_edges = st->edge_class.size();
    r->edge_vertices = st->edge_vertices.data();
    r->edge_class = st->edge_class.data();
    r->num_polylines = st->polyline_start.size() - 1;
    r->polyline_start = st->polyline_start.data();
    r->num_points = st->point_x.size();
    r->point_x = st->point_x.data();
    r->point_y = st->point_y.data();
    r->internal = st;
    *result = r;
    write_error(err, err_len, "");
    return WMO_OK;
  } catch (const OracleError& e) {
    delete st;
    write_error(err, err_len, e.what());
    return e.code;
  } catch (const CGAL::Failure_exception& e) {
    delete st;
    write_error(err, err_len, e.what());
    return WMO_ERR_CGAL;
  } catch (const std::exception& e) {
    delete st;
    write_error(err, err_len, e.what());
    return WMO_ERR_INTERNAL;
  } catch (...) {
    delete st;
    write_error(err, err_len, "unknown C++ exception");
    return WMO_ERR_INTERNAL;
  }
}

extern "C" void wmo_free(wmo_result* result) {
  if (result == nullptr) return;
  delete static_cast<Storage*>(result->internal);
  delete result;
}

extern "C" int wmo_self_intersections(const double* xyz, size_t num_vertices,
                                      const uint32_t* faces, size_t num_faces,
                                      int* does_intersect, uint32_t* pairs, size_t max_pairs,
                                      size_t* num_pairs, char* err, size_t err_len) {
  if (does_intersect == nullptr || num_pairs == nullptr || (max_pairs > 0 && pairs == nullptr)) {
    write_error(err, err_len, "output pointer is null");
    return WMO_ERR_INPUT;
  }
  *does_intersect = 0;
  *num_pairs = 0;
  try {
    bool does = false;
    const auto found = self_intersecting_pairs(xyz, num_vertices, faces, num_faces, does);
    for (size_t i = 0; i < found.size() && i < max_pairs; ++i) {
      pairs[2 * i] = found[i].first;
      pairs[2 * i + 1] = found[i].second;
    }
    *num_pairs = found.size();
    *does_intersect = does ? 1 : 0;
    write_error(err, err_len, "");
    return WMO_OK;
  } catch (const OracleError& e) {
    write_error(err, err_len, e.what());
    return e.code;
  } catch (const CGAL::Failure_exception& e) {
    write_error(err, err_len, e.what());
    return WMO_ERR_CGAL;
  } catch (const std::exception& e) {
    write_error(err, err_len, e.what());
    return WMO_ERR_INTERNAL;
  } catch (...) {
    write_error(err, err_len, "unknown C++ exception");
    return WMO_ERR_INTERNAL;
  }
}
