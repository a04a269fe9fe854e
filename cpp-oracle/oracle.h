//! Input: a closed, consistently oriented triangle mesh (vertex coordinates
//! as doubles, each an exact dyadic rational; faces as uint32 index
//! triples) and an exact rational level c given as two decimal strings.
//! Output: an independent, exact weak-Morse classification of the plane
//! z = c (SPEC.md section 3) computed with CGAL's Epeck kernel, and the
//! polylines of CGAL::Polygon_mesh_slicer with exact "p/q" coordinates.
//!
//! This is a test oracle for the Rust crate `wmslice` (feature
//! `cgal-oracle`). It is derived from SPEC.md, not from the Rust code.
//!
//! C API (all functions are exception-free; every C++ exception is caught
//! and turned into an error code):
//!
//!   int  wmo_classify(xyz, num_vertices, faces, num_faces,
//!                     level_num, level_den, &result, err, err_len);
//!   void wmo_free(result);
//!   int  wmo_self_intersections(xyz, num_vertices, faces, num_faces,
//!                               &does_intersect, pairs, max_pairs,
//!                               &num_pairs, err, err_len);
//!
//! On success wmo_classify returns WMO_OK and stores a result owned by the
//! shim in *result; the caller releases it with wmo_free (exactly once). On
//! failure it returns a non-zero WMO_ERR_* code, stores NULL in *result and
//! writes a NUL-terminated message into err (truncated to err_len bytes;
//! err may be NULL when err_len is 0).
#ifndef WMSLICE_CGAL_ORACLE_H
#define WMSLICE_CGAL_ORACLE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Return codes of wmo_classify. */
enum {
  WMO_OK = 0,
  WMO_ERR_INPUT = 1,    /* non-finite coordinate, index out of range, ... */
  WMO_ERR_LEVEL = 2,    /* level strings not integers, or zero denominator */
  WMO_ERR_MESH = 3,     /* not a closed oriented 2-manifold triangle mesh */
  WMO_ERR_CGAL = 4,     /* a CGAL precondition/assertion failed */
  WMO_ERR_INTERNAL = 5  /* any other C++ exception (incl. bad_alloc) */
};

/* vertex_sign: sign(z - c). */
enum { WMO_BELOW = -1, WMO_ON = 0, WMO_ABOVE = 1 };

/* face_in_plane: a face with all three vertices on the plane, with the
 * facing of its (x, y) projection (exact orient2d). */
enum {
  WMO_FACE_OFF = 0,  /* not in the plane */
  WMO_FACE_UP = 1,   /* counter-clockwise: outward normal +z */
  WMO_FACE_DOWN = 2, /* clockwise: outward normal -z */
  WMO_FACE_FLAT = 3  /* zero projected area */
};

/* edge_class of an in-plane edge (both ends on the plane). */
enum {
  WMO_EDGE_INTERIOR = 0,    /* both faces in the plane */
  WMO_EDGE_RIDGE = 1,       /* both opposite vertices below (S_NO) */
  WMO_EDGE_VALLEY = 2,      /* both opposite vertices above (S_NO) */
  WMO_EDGE_TRANSVERSAL = 3, /* opposite vertices of opposite signs (S_O) */
  WMO_EDGE_BOUNDARY = 4,    /* exactly one face in the plane, not S_O */
  WMO_EDGE_BOUNDARY_SO = 5  /* boundary edge that is also S_O: an up face
                               with its off-plane neighbour above, or a
                               down face with it below */
};

/* vertex_extremum. */
enum { WMO_NOT_EXTREMAL = 0, WMO_MIN = 1, WMO_MAX = 2 };

/* The answer. Every array is owned by the result and lives until wmo_free. */
typedef struct wmo_result {
  size_t num_vertices;
  const int8_t *vertex_sign;        /* [num_vertices], WMO_BELOW/ON/ABOVE */
  const uint8_t *vertex_extremum;   /* [num_vertices], WMO_MIN/MAX or 0 */
  const uint32_t *vertex_branches;  /* [num_vertices], S_O pieces ending at
                                       the vertex (0 when off the plane):
                                       in-plane transversal edges + boundary
                                       S_O edges + crossed faces having it as
                                       their zero vertex */
  size_t num_faces;
  const uint8_t *face_in_plane;     /* [num_faces], WMO_FACE_* */
  size_t num_edges;                 /* in-plane edges only */
  const uint32_t *edge_vertices;    /* [2 * num_edges], each pair smaller id
                                       first, pairs ascending */
  const uint8_t *edge_class;        /* [num_edges], WMO_EDGE_* */
  size_t num_polylines;             /* from CGAL::Polygon_mesh_slicer */
  const size_t *polyline_start;     /* [num_polylines + 1]: polyline i is
                                       points polyline_start[i] ..
                                       polyline_start[i + 1] - 1; a closed
                                       polyline repeats its first point */
  size_t num_points;
  const char *const *point_x;       /* [num_points], exact "p/q" or "p" in
                                       lowest terms (q > 0) */
  const char *const *point_y;       /* [num_points], idem */
  void *internal;                   /* owned storage; do not touch */
} wmo_result;

/* Classifies the plane z = level_num / level_den.
 * xyz: 3 * num_vertices doubles (x, y, z per vertex), all finite.
 * faces: 3 * num_faces vertex ids, counter-clockwise seen from outside.
 * level_num, level_den: decimal integers ("-7", "20"), den != 0. */
int wmo_classify(const double *xyz, size_t num_vertices,
                 const uint32_t *faces, size_t num_faces,
                 const char *level_num, const char *level_den,
                 wmo_result **result, char *err, size_t err_len);

/* Releases a result of wmo_classify; NULL is ignored. */
void wmo_free(wmo_result *result);

/* Self-intersection of a closed, oriented 2-manifold triangle mesh (same
 * input as wmo_classify), decided exactly (Epeck) by
 * CGAL::Polygon_mesh_processing::does_self_intersect (*does_intersect: 0
 * or 1) and self_intersections: the face pairs it reports, each smaller id
 * first, ascending, without repeats; the first min(count, max_pairs) are
 * written to pairs[2 * i], pairs[2 * i + 1] and the count to *num_pairs.
 * CGAL 5.5's notion (Polygon_mesh_processing/self_intersections.h): two
 * faces on an edge intersect when coplanar with their opposite vertices on
 * one side (a fold); two faces on one vertex when the edge of one opposite
 * that vertex meets the other (closed sets); others when the closed
 * triangles meet; a degenerate face is reported as the pair (f, f) and
 * nowhere else. Returns WMO_OK or a WMO_ERR_* code with a message in err,
 * as wmo_classify. */
int wmo_self_intersections(const double *xyz, size_t num_vertices,
                           const uint32_t *faces, size_t num_faces,
                           int *does_intersect, uint32_t *pairs, size_t max_pairs,
                           size_t *num_pairs, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* WMSLICE_CGAL_ORACLE_H */
