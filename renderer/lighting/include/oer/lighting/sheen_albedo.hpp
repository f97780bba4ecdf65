#pragma once
// The directional albedo of the KHR_materials_sheen BRDF (Khronos, 2021), the "Charlie" sheen of
// A. Estevez and C. Kulla, "Production Friendly Microfacet Sheen BRDF", Sony Pictures
// Imageworks, 2017: with white sheen colour,
//   E_sheen(n.v, r) = integral over the hemisphere of D(h) V(v, l) n.l dl,
//   D(h) = (2 + 1 / a) sin(theta_h)^(1 / a) / (2 pi),  a = r^2,
//   V = 1 / ((1 + L(n.v) + L(n.l)) 4 n.v n.l),
// L being their fitted Smith-like lambda (the extension's "Sheen visibility"). The renderer
// scales the sheen lobe by it (sheen colour times E_sheen times the incident radiance), and the
// material beneath by 1 - max(sheen colour) E_sheen, the extension's albedo scaling, so that a
// white furnace keeps its energy. Tabulated on the CPU as the split sum's DFG table is
// (split_sum.hpp), by importance sampling of D, and clamped to 1 (the fitted visibility exceeds
// it at grazing view and low roughness).
#include <vector>

namespace oer {

struct SheenAlbedoTable {
    int size = 0;
    // size x size values: row j at sheen roughness (j + 0.5) / size, column i at n.v =
    // (i + 0.5) / size (texel centres, as an R32F texture sampled with clamping).
    std::vector<float> albedo;
};

// Throws oer::Error (InvalidInput) for size outside [2, 256] or samples outside [1, 65536].
// Deterministic (Hammersley points).
SheenAlbedoTable sheen_albedo_table(int size = 32, int samples = 1024);

// The table read bilinearly as the shader does (clamped at the edges).
double sample_sheen_albedo(const SheenAlbedoTable& table, double n_dot_v, double roughness);

}  // namespace oer
