//! Input: byte strings that once crashed or stressed a loader (found by the
//! `fuzz/` targets or written against a known weak spot). Output: the
//! check the parser fuzz targets run, their own code
//! (`fuzz/fuzz_targets/common.rs`: load without panic; snap what a 3MF
//! transform leaves off the doubles; as read and with collapsed faces
//! removed, a mesh that validates passes the topology invariants), one
//! named test per input.

use wmslice::mesh::io::MeshFormat;

/// The fuzz targets' check itself (`check(bytes, format)`).
#[path = "../fuzz/fuzz_targets/common.rs"]
mod fuzz_common;
use fuzz_common::check;

#[test]
fn stress_stl_header_only_with_max_count() {
    let mut b = vec![b' '; 80];
    b.extend_from_slice(&u32::MAX.to_le_bytes());
    check(&b, MeshFormat::StlBinary);
    b[..6].copy_from_slice(b"solid ");
    check(&b, MeshFormat::StlBinary);
}

#[test]
fn stress_obj_extreme_indices_and_continuations() {
    check(
        b"v 1 2 3\\\n\nf -1 -1 -1\nf 4294967296 1 1\nf -9223372036854775808 1 1\nf 99999999999999999999999 1 1\nf 1\\",
        MeshFormat::Obj,
    );
}

#[test]
fn stress_off_counts_at_the_limits() {
    check(b"OFF\n18446744073709551615 0 0\n", MeshFormat::Off);
    check(b"OFF 0 18446744073709551615\n", MeshFormat::Off);
    check(
        b"OFF\n1 1\n0 0 0\n18446744073709551615 0 0 0\n",
        MeshFormat::Off,
    );
}

#[test]
fn stress_ply_zero_size_elements_and_huge_lists() {
    check(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement nothing 4000000000\nend_header\n",
        MeshFormat::PlyBinaryLittleEndian,
    );
    check(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n\xff\xff\xff\xff",
        MeshFormat::PlyBinaryLittleEndian,
    );
}
