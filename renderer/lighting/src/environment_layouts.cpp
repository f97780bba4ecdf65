// Cube maps (six faces or a cross) and mirror-ball probes resampled to equirect
// (see oer/environment_layouts.hpp). Every output pixel looks up the source at its own
// direction (oer::equirect::Grid) and samples it bilinearly.
#include "oer/lighting/environment_layouts.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cube_faces.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer {

namespace {

constexpr int kMaxOutputWidth = 32768;

[[noreturn]] void invalid(const std::string& what) {
    throw Error(ErrorKind::InvalidInput, what);
}

void check_image(const HdrImage& image, const std::string& what) {
    if (image.width <= 0 || image.height <= 0) {
        invalid(what + " is empty (" + std::to_string(image.width) + "x" +
                std::to_string(image.height) + ")");
    }
    if (image.pixels.size() != image.pixel_count() * 3) {
        invalid(what + " has " + std::to_string(image.pixels.size()) + " values for " +
                std::to_string(image.width) + "x" + std::to_string(image.height) + " RGB pixels");
    }
}

HdrImage make_output(int out_width) {
    if (out_width < 2 || out_width > kMaxOutputWidth) {
        invalid("equirect output width " + std::to_string(out_width) + " is outside [2, " +
                std::to_string(kMaxOutputWidth) + "]");
    }
    return HdrImage(out_width, out_width / 2);
}

// Bilinear sample at continuous position (u, v) in pixel units (pixel centres at +0.5),
// clamped to the image's edge texels.
void sample_bilinear(const HdrImage& image, double u, double v, float* out) {
    const double x = std::clamp(u - 0.5, 0.0, double(image.width - 1));
    const double y = std::clamp(v - 0.5, 0.0, double(image.height - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
    const float fx = float(x - x0), fy = float(y - y0);
    const float* a = image.at(x0, y0);
    const float* b = image.at(x1, y0);
    const float* c = image.at(x0, y1);
    const float* d = image.at(x1, y1);
    for (int k = 0; k < 3; ++k) {
        const float top = a[k] + (b[k] - a[k]) * fx;
        const float bottom = c[k] + (d[k] - c[k]) * fx;
        out[k] = top + (bottom - top) * fy;
    }
}

// Copies an n x n cell of the cross, rotated by 180 degrees if asked.
HdrImage extract_face(const HdrImage& cross, int cell_x, int cell_y, int n, bool rotate_180) {
    HdrImage face(n, n);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const int sx = rotate_180 ? n - 1 - x : x;
            const int sy = rotate_180 ? n - 1 - y : y;
            const float* source = cross.at(cell_x * n + sx, cell_y * n + sy);
            std::copy(source, source + 3, face.at(x, y));
        }
    }
    return face;
}

}  // namespace

HdrImage equirect_from_cube_faces(const std::array<const HdrImage*, 6>& faces, int out_width) {
    static const char* const names[6] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
    for (int i = 0; i < 6; ++i) {
        if (faces[i] == nullptr) {
            invalid(std::string("cube face ") + names[i] + " is missing");
        }
        check_image(*faces[i], std::string("cube face ") + names[i]);
        if (faces[i]->width != faces[i]->height) {
            invalid(std::string("cube face ") + names[i] + " is not square (" +
                    std::to_string(faces[i]->width) + "x" + std::to_string(faces[i]->height) + ")");
        }
        if (faces[i]->width != faces[0]->width) {
            invalid(std::string("cube face ") + names[i] + " is " +
                    std::to_string(faces[i]->width) + " pixels wide, face +X is " +
                    std::to_string(faces[0]->width));
        }
    }
    HdrImage out = make_output(out_width);
    const equirect::Grid grid(out.width, out.height);
    const double n = faces[0]->width;
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            const auto c = detail::cube_lookup(grid.direction(x, y));
            sample_bilinear(*faces[c.face], c.s * n, c.t * n, out.at(x, y));
        }
    }
    return out;
}

HdrImage equirect_from_cross(const HdrImage& cross, int out_width) {
    check_image(cross, "cube cross");
    const std::string size = std::to_string(cross.width) + "x" + std::to_string(cross.height);
    const bool horizontal = 3 * std::int64_t(cross.width) == 4 * std::int64_t(cross.height);
    const bool vertical = 4 * std::int64_t(cross.width) == 3 * std::int64_t(cross.height);
    if (!horizontal && !vertical) {
        invalid("cube cross is " + size +
                ": the aspect must be 4:3 (horizontal) or 3:4 (vertical)");
    }
    const int n = horizontal ? cross.width / 4 : cross.width / 3;
    if (n < 1 || (horizontal ? (cross.width % 4 != 0 || cross.height % 3 != 0)
                             : (cross.width % 3 != 0 || cross.height % 4 != 0))) {
        invalid("cube cross is " + size + ": not a whole number of square faces");
    }
    // Cells (column, row) in the order +X, -X, +Y, -Y, +Z, -Z.
    struct Cell {
        int x, y;
    };
    const std::array<Cell, 6> cells =
        horizontal ? std::array<Cell, 6>{Cell{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}}
                   : std::array<Cell, 6>{Cell{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {1, 3}};
    std::array<HdrImage, 6> faces;
    std::array<const HdrImage*, 6> pointers{};
    for (int i = 0; i < 6; ++i) {
        const bool rotate = vertical && i == 5;  // -Z of a vertical cross is stored upside down
        faces[i] = extract_face(cross, cells[i].x, cells[i].y, n, rotate);
        pointers[i] = &faces[i];
    }
    return equirect_from_cube_faces(pointers, out_width);
}

HdrImage equirect_from_mirror_ball(const HdrImage& probe, int out_width) {
    check_image(probe, "mirror-ball probe");
    if (probe.width != probe.height) {
        invalid("mirror-ball probe is " + std::to_string(probe.width) + "x" +
                std::to_string(probe.height) + ": it must be square");
    }
    HdrImage out = make_output(out_width);
    const equirect::Grid grid(out.width, out.height);
    const double size = probe.width;
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            // r = 2 (n . e) n - e gives n parallel to r + e (e = +Z, towards the camera).
            const glm::dvec3 r = grid.direction(x, y);
            glm::dvec3 h = r + glm::dvec3(0.0, 0.0, 1.0);
            double u, v;
            const double len = glm::length(h);
            if (len < 1e-12) {
                u = 1.0, v = 0.0;  // exactly -Z: the whole rim; take a point of it
            } else {
                h /= len;
                u = h.x, v = h.y;
                const double rho = std::sqrt(u * u + v * v);
                if (rho > 1.0) {  // rounding only: clamp to the disc
                    u /= rho, v /= rho;
                }
            }
            sample_bilinear(probe, (u + 1.0) * 0.5 * size, (1.0 - v) * 0.5 * size, out.at(x, y));
        }
    }
    return out;
}

}  // namespace oer
