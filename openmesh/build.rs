//! Build script: compiles the C++ side of the cxx bridge (cpp/openmesh_bridge.cpp, C++17) and links
//! Debian's OpenMesh (`libopenmesh-dev`: headers in /usr/include/OpenMesh, libOpenMeshCore.so,
//! libOpenMeshTools.so). `OPENMESH_INCLUDE_DIR` / `OPENMESH_LIB_DIR` override the default system
//! locations.

fn main() {
    println!("cargo:rerun-if-changed=src/lib.rs");
    println!("cargo:rerun-if-changed=cpp/openmesh_bridge.cpp");
    println!("cargo:rerun-if-changed=cpp/openmesh_bridge.h");
    println!("cargo:rerun-if-env-changed=OPENMESH_INCLUDE_DIR");
    println!("cargo:rerun-if-env-changed=OPENMESH_LIB_DIR");
    let mut build = cxx_build::bridge("src/lib.rs");
    build
        .file("cpp/openmesh_bridge.cpp")
        .std("c++17")
        // OpenMesh's headers use M_PI and friends.
        .define("_USE_MATH_DEFINES", None)
        .flag_if_supported("-Wno-deprecated-declarations")
        .flag_if_supported("-Wno-unused-parameter");
    if let Ok(dir) = std::env::var("OPENMESH_INCLUDE_DIR") {
        build.include(dir);
    }
    build.compile("gbsurf_openmesh_bridge");
    if let Ok(dir) = std::env::var("OPENMESH_LIB_DIR") {
        println!("cargo:rustc-link-search=native={dir}");
    }
    println!("cargo:rustc-link-lib=dylib=OpenMeshTools");
    println!("cargo:rustc-link-lib=dylib=OpenMeshCore");
}
