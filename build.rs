//! Build script: does nothing unless the `openmesh` feature is on. With it, compiles the C++ side
//! of the cxx bridge (cpp/bridge/*.cpp, C++17) and links Debian's OpenMesh
//! (`libopenmesh-dev`: headers in /usr/include/OpenMesh, libOpenMeshCore.so, libOpenMeshTools.so).
//! `OPENMESH_INCLUDE_DIR` / `OPENMESH_LIB_DIR` override the default system locations.

fn main() {
    #[cfg(feature = "openmesh")]
    openmesh::build();
}

#[cfg(feature = "openmesh")]
mod openmesh {
    pub fn build() {
        println!("cargo:rerun-if-changed=src/openmesh.rs");
        println!("cargo:rerun-if-changed=cpp/bridge/openmesh_bridge.cpp");
        println!("cargo:rerun-if-changed=cpp/bridge/openmesh_bridge.h");
        println!("cargo:rerun-if-env-changed=OPENMESH_INCLUDE_DIR");
        println!("cargo:rerun-if-env-changed=OPENMESH_LIB_DIR");
        let mut build = cxx_build::bridge("src/openmesh.rs");
        build
            .file("cpp/bridge/openmesh_bridge.cpp")
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
}
