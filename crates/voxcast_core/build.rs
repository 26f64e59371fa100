//! Names, once, the targets where the CPU renderer's eight lanes exist (`cfg(lanes)`):
//! x86-64 (AVX2, SSE 4.1), 64-bit ARM (NEON) and WebAssembly built with its 128-bit SIMD
//! (`simd128`, which the page's build enables: `web/build.sh`). Elsewhere every march is the
//! scalar one.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(lanes)");
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let features = std::env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let simd128 = features.split(',').any(|f| f == "simd128");
    if arch == "x86_64" || arch == "aarch64" || (arch == "wasm32" && simd128) {
        println!("cargo::rustc-cfg=lanes");
    }
}
