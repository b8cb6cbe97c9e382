// gbsurf_convert: read any mesh format OpenMesh reads (OBJ, OFF, PLY, STL, OM), convert it to a
// smooth GB-patch surface, write the triangle mesh (with vertex normals) in any format OpenMesh
// writes, chosen by the extension.
//
//   gbsurf_convert input.off output.ply [--method dual|topology|doo-sabin|catmull-clark]
//                  [--resolution N] [--levels N] [--nets nets.obj]
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <gbsurf/openmesh.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace {
int usage() {
    std::cerr << "usage: gbsurf_convert INPUT OUTPUT [--method dual|topology|doo-sabin|catmull-clark]"
                 " [--resolution N] [--levels N] [--nets NETS.obj]\n";
    return 2;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) return usage();
    const std::string input = argv[1], output = argv[2];
    std::string nets;
    try {
        gbsurf::options opt;  // throws GBSURF_ERR_VERSION if header and library disagree
        for (int i = 3; i < argc; ++i) {
            const std::string a = argv[i];
            if (i + 1 >= argc) return usage();
            const std::string v = argv[++i];
            if (a == "--method") opt.method(gbsurf::parse_method(v));
            else if (a == "--resolution") opt.resolution(static_cast<uint32_t>(std::stoul(v)));
            else if (a == "--levels") opt.levels(static_cast<uint32_t>(std::stoul(v)));
            else if (a == "--nets") nets = v;
            else return usage();
        }
        opt.validate();

        OpenMesh::PolyMesh_ArrayKernelT<> in;
        if (!OpenMesh::IO::read_mesh(in, input)) {
            std::cerr << "gbsurf_convert: OpenMesh cannot read " << input << "\n";
            return 1;
        }
        gbsurf::result r = gbsurf::openmesh::convert_to_result(in, opt);
        gbsurf::openmesh::TriMesh out = gbsurf::openmesh::to_trimesh(r);
        if (!OpenMesh::IO::write_mesh(out, output, OpenMesh::IO::Options::VertexNormal)) {
            std::cerr << "gbsurf_convert: OpenMesh cannot write " << output << "\n";
            return 1;
        }
        if (!nets.empty()) {
            gbsurf::openmesh::PolyMesh n = gbsurf::openmesh::control_nets(r);
            if (!OpenMesh::IO::write_mesh(n, nets)) {
                std::cerr << "gbsurf_convert: OpenMesh cannot write " << nets << "\n";
                return 1;
            }
        }
        const GbsurfReport rep = r.report();
        std::cout << input << ": " << rep.patches << " patches, " << out.n_vertices() << " vertices, "
                  << out.n_faces() << " triangles, closed " << rep.closed << ", max G1 " << rep.max_g1_deg
                  << " deg, " << r.curve_count() << " curves\n";
        for (const auto& w : r.warnings()) std::cout << "warning: " << w << "\n";
    } catch (const gbsurf::error& e) {
        std::cerr << "gbsurf_convert: " << e.what() << "\n";
        return 10 + static_cast<int>(e.code());
    } catch (const std::exception& e) {
        std::cerr << "gbsurf_convert: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
