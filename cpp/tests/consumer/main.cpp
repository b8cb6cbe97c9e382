// Consumer of the installed package: converts the file given (or fails with its error code).
#include <gbsurf.hpp>

#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: consumer_app MESH\n";
        return 2;
    }
    try {
        gbsurf::result r = gbsurf::convert_file(argv[1], gbsurf::options().resolution(4));
        std::cout << "gbsurf " << gbsurf::version() << ": " << r.vertex_count() << " vertices, "
                  << r.triangle_count() << " triangles\n";
        return r.triangle_count() > 0 ? 0 : 1;
    } catch (const gbsurf::error& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
}
