//! Input: the Cargo feature `cgal-oracle` (seen as `CARGO_FEATURE_CGAL_ORACLE`)
//! and the git checkout. Output: the build commit as `WMSLICE_BUILD_COMMIT`;
//! with the feature, the C++ CGAL test oracle `cpp-oracle/oracle.cpp`
//! compiled (C++17, `-O1`) into a static library and linked with `gmp`,
//! `mpfr` and `stdc++`; without it, nothing (the default build needs
//! neither CGAL nor a C++ toolchain).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    // The build commit, for certificates (absent outside a git checkout).
    // Watching a path that does not exist would rebuild every time.
    for watched in [".git/HEAD", ".git/refs/heads"] {
        if std::path::Path::new(watched).exists() {
            println!("cargo:rerun-if-changed={watched}");
        }
    }
    if let Ok(o) = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
    {
        if o.status.success() {
            println!(
                "cargo:rustc-env=WMSLICE_BUILD_COMMIT={}",
                String::from_utf8_lossy(&o.stdout).trim()
            );
        }
    }
    if std::env::var_os("CARGO_FEATURE_CGAL_ORACLE").is_some() {
        #[cfg(feature = "cgal-oracle")]
        build_oracle();
    }
}

/// Compiles the oracle (about 30 s: CGAL is header-only and heavy).
#[cfg(feature = "cgal-oracle")]
fn build_oracle() {
    println!("cargo:rerun-if-changed=cpp-oracle/oracle.cpp");
    println!("cargo:rerun-if-changed=cpp-oracle/oracle.h");
    cc::Build::new()
        .cpp(true)
        .std("c++17")
        .opt_level(1)
        .debug(false)
        .file("cpp-oracle/oracle.cpp")
        .include("cpp-oracle")
        .compile("wmslice_cgal_oracle");
    for lib in ["gmp", "mpfr", "stdc++"] {
        println!("cargo:rustc-link-lib={lib}");
    }
}
