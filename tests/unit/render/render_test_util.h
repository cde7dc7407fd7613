// Shared helpers for the render tests: small models and a PNG read back with VTK.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

#include <unistd.h>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include "engine/blocks.h"
#include "engine/model.h"
#include "render/scene.h"

namespace odec::test {

// A PNG read back: width x height RGB pixels, rows from the bottom as VTK gives them.
struct Picture {
    int width = 0, height = 0, components = 0;
    std::vector<unsigned char> rgb;

    render::Rgb at(int x, int y) const {
        const unsigned char* p = &rgb[(static_cast<size_t>(y) * width + x) * components];
        return {p[0] / 255.0, p[1] / 255.0, p[2] / 255.0};
    }
    // Pixels within tol (0..1 per channel) of colour c.
    int count_near(const render::Rgb& c, double tol) const {
        int n = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const render::Rgb p = at(x, y);
                if (std::abs(p[0] - c[0]) <= tol && std::abs(p[1] - c[1]) <= tol && std::abs(p[2] - c[2]) <= tol) ++n;
            }
        return n;
    }
    template <class Pred>
    int count_if(Pred pred) const {
        int n = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                if (pred(at(x, y))) ++n;
        return n;
    }
    int n_distinct_colours() const {
        std::vector<int> seen;
        for (size_t i = 0; i + 2 < rgb.size(); i += components) seen.push_back(rgb[i] << 16 | rgb[i + 1] << 8 | rgb[i + 2]);
        std::sort(seen.begin(), seen.end());
        return static_cast<int>(std::unique(seen.begin(), seen.end()) - seen.begin());
    }
};

inline bool read_png(const std::string& path, Picture& pic) {
    if (access(path.c_str(), R_OK) != 0) return false;
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* img = reader->GetOutput();
    int dims[3];
    img->GetDimensions(dims);
    pic.width = dims[0];
    pic.height = dims[1];
    pic.components = img->GetNumberOfScalarComponents();
    if (pic.width <= 0 || pic.height <= 0 || pic.components < 3) return false;
    const auto* data = static_cast<const unsigned char*>(img->GetScalarPointer());
    pic.rgb.assign(data, data + static_cast<size_t>(pic.width) * pic.height * pic.components);
    return true;
}

inline std::string out_dir() {
    const std::string dir = "render-test-output";
    std::string cmd = "mkdir -p " + dir;
    if (std::system(cmd.c_str()) != 0) return ".";
    return dir;
}

// An nx x ny x nz wall of unit bricks, group "rock" for the lower half and "fill" above.
inline Model brick_model(int nx, int ny, int nz, double size = 1.0) {
    Model m;
    m.title = "Test wall";
    const int rock = m.group_index("rock", true);
    const int fill = m.group_index("fill", true);
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const bool upper = 2 * k >= nz;
                add_block(m, make_brick(i * size, (i + 1) * size, j * size, (j + 1) * size, k * size, (k + 1) * size),
                          upper ? 2 : 1, upper ? fill : rock, upper ? 2 : 1);
            }
    return m;
}

} // namespace odec::test
