//! With the `cholmod` feature, compiles the C shim over SuiteSparse's CHOLMOD
//! (src/min_norm/cholmod_shim.c), whose headers Debian's `libsuitesparse-dev` puts under
//! /usr/include/suitesparse; the library itself is linked by the `#[link]` in
//! src/min_norm/updatable_factor.rs. The default build compiles no C here and links no
//! SuiteSparse.
fn main() {
    let shim = "src/min_norm/cholmod_shim.c";
    println!("cargo:rerun-if-changed={shim}");
    if std::env::var_os("CARGO_FEATURE_CHOLMOD").is_none() {
        return;
    }
    cc::Build::new()
        .file(shim)
        .include("/usr/include/suitesparse")
        .warnings(true)
        .compile("packbench_cholmod_shim");
}
