// The extensions' layers of a material (brdf.glsl's SurfaceLayers) in two RGBA32UI targets of
// the G-buffer: the geometry pass packs them (geometry.frag, MATERIAL_LAYERS 1) and the shading
// pass unpacks them (shade.frag, SURFACE 4), so that layered materials are shaded deferred, once
// a sample, as plain ones are. 17 values in 256 bits: the coat's normal octahedral in two snorm16
// (Cigolle, Donow, Evangelakos, Mara, McGuire and Meyer, "A Survey of Efficient Representations
// for Independent Unit Vectors", JCGT 2014: under 1e-4 radians off), the coat's and the
// transmission's weights in unorm8 (a weight of 1/510 at most off, as an 8-bit texture's), every
// other value a half float (relative error under 4.9e-4).

// The unit vector n on the octahedron |x| + |y| + |z| = 1, its lower half folded over the upper
// half's diagonals, as a point of [-1, 1]^2.
vec2 octahedral_encode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 signs = vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return n.z >= 0.0 ? n.xy : (1.0 - abs(n.yx)) * signs;
}

// octahedral_encode's inverse, of unit length.
vec3 octahedral_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    vec2 signs = vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    if (n.z < 0.0) {
        n.xy = (1.0 - abs(n.yx)) * signs;
    }
    return normalize(n);
}

// first: f0 (rgb), f90, the coat's normal, the coat's and the sheen's roughness; second: the
// sheen's colour (rgb), the index of refraction, the volume's transmittance (rgb), and the coat's
// and the transmission's weights.
void pack_layers(SurfaceLayers layers, out uvec4 first, out uvec4 second) {
    first = uvec4(packHalf2x16(layers.dielectric_f0.rg),
                  packHalf2x16(vec2(layers.dielectric_f0.b, layers.dielectric_f90)),
                  packSnorm2x16(octahedral_encode(layers.clearcoat_normal)),
                  packHalf2x16(vec2(layers.clearcoat_roughness, layers.sheen_roughness)));
    second = uvec4(packHalf2x16(layers.sheen_color.rg),
                   packHalf2x16(vec2(layers.sheen_color.b, layers.ior)),
                   packHalf2x16(layers.volume_transmittance.rg),
                   (packHalf2x16(vec2(layers.volume_transmittance.b, 0.0)) & 0xffffu) |
                       (packUnorm4x8(vec4(layers.clearcoat, layers.transmission, 0.0, 0.0))
                        << 16));
}

SurfaceLayers unpack_layers(uvec4 first, uvec4 second) {
    vec2 f0_rg = unpackHalf2x16(first.x);
    vec2 f0_b_f90 = unpackHalf2x16(first.y);
    vec2 roughnesses = unpackHalf2x16(first.w);
    vec2 sheen_b_ior = unpackHalf2x16(second.y);
    vec4 weights = unpackUnorm4x8(second.w >> 16);
    return SurfaceLayers(sheen_b_ior.y, vec3(f0_rg, f0_b_f90.x), f0_b_f90.y, weights.x,
                         roughnesses.x, octahedral_decode(unpackSnorm2x16(first.z)),
                         vec3(unpackHalf2x16(second.x), sheen_b_ior.x), roughnesses.y, weights.y,
                         vec3(unpackHalf2x16(second.z), unpackHalf2x16(second.w).x));
}
