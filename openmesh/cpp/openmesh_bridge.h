// C++ side of the gbsurf <-> OpenMesh cxx bridge (cargo feature `openmesh`).
// Meshes cross the bridge as flat arrays (MeshData, defined by cxx from src/ffi/openmesh.rs).
// Every function reports failure by throwing std::runtime_error, which cxx turns into a Rust Err.
#pragma once
#include "rust/cxx.h"

namespace gbsurf_om {

struct MeshData;

// Reads any format OpenMesh knows (by extension: obj, off, ply, stl, om) with double positions.
MeshData read_mesh(rust::Str path);
// Writes `mesh` (with vertex normals when `normals` is filled) in the format named by the
// extension; `precision` significant digits for text formats.
void write_mesh(const MeshData &mesh, rust::Str path, bool binary, unsigned int precision);
// OpenMesh's uniform Catmull-Clark subdivider (Tools/Subdivider/Uniform/CatmullClarkT.hh).
MeshData catmull_clark(const MeshData &mesh, unsigned int levels);

} // namespace gbsurf_om
