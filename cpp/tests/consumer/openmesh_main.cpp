// Consumer of the installed package with the OpenMesh adapter.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <gbsurf/openmesh.hpp>

#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    OpenMesh::PolyMesh_ArrayKernelT<> in;
    if (!OpenMesh::IO::read_mesh(in, argv[1])) return 1;
    try {
        auto out = gbsurf::openmesh::convert(in, gbsurf::options().resolution(4));
        std::cout << out.n_vertices() << " vertices, " << out.n_faces() << " triangles\n";
        return out.n_faces() > 0 ? 0 : 1;
    } catch (const gbsurf::error& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
}
