//! Compiles the C shim over SuiteSparse's CHOLMOD (src/min_norm/cholmod_shim.c), whose headers
//! Debian's `libsuitesparse-dev` puts under /usr/include/suitesparse; the library itself is
//! linked by the `#[link]` in src/min_norm/updatable_factor.rs.
fn main() {
    let shim = "src/min_norm/cholmod_shim.c";
    println!("cargo:rerun-if-changed={shim}");
    cc::Build::new()
        .file(shim)
        .include("/usr/include/suitesparse")
        .warnings(true)
        .compile("packbench_cholmod_shim");
}
