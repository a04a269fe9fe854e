//! Input: arbitrary bytes, taken as the XML of a 3MF model part. Output:
//! nothing; panics only on a bug. The bytes are stored (uncompressed) as
//! `3D/3dmodel.model` in a fresh zip package, so the fuzzer reaches the XML
//! and build stages that mutated deflate streams almost never reach.
#![no_main]

use std::io::Write;

use libfuzzer_sys::fuzz_target;
use wmslice::mesh::io::MeshFormat;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let mut zw = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    if zw.start_file("3D/3dmodel.model", options).is_err() || zw.write_all(data).is_err() {
        return;
    }
    let Ok(cursor) = zw.finish() else { return };
    common::check(&cursor.into_inner(), MeshFormat::ThreeMf);
});
