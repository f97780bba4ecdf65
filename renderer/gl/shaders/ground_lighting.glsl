// The opaque ground plane's irradiance at a point of it: the lights' through their shadows on
// the plane and the residual's through the transfer's occlusion of it. Shared by the ground's
// own shading (shade.frag, SURFACE 2 and 3) and by what a glossy object reflects of the floor
// (surface_shading.glsl's floor_radiance, SPECULAR 1), so that a product's reflection of the
// floor holds the shadows drawn on it. Needs LIGHTS_ON's u_light_direction and u_light_share, and
// u_attenuation_base (surface_shading.glsl), declared before it is included.
#if GROUND_SURFACE || SPECULAR
// The ground plane's normal never changes: its irradiance per set is computed once per frame
// on the CPU, and no SH is evaluated for its points.
uniform vec3 u_flat_irradiance[1 + LIGHTS_ON];
#if LIGHTS_ON > 0 && SHADOWS
// Each light's visibility on the ground plane, baked once per shadow map (the ground's depth
// in light space is a function of the shadow-map uv), read with one bilinear fetch.
layout(binding = GROUND_VISIBILITY_UNIT) uniform sampler2DArray u_ground_visibility;
#endif
#if TRANSFER
// The transfer's irradiance over the ground's grid (GroundTransfer), one texel per receiver,
// read bilinearly; clamped beyond the grid, whose edge holds the unoccluded ground's.
layout(binding = GROUND_TRANSFER_UNIT) uniform sampler2D u_ground_transfer;
uniform vec4 u_ground_transfer_rect;     // the grid's lowest x and z, 1 / its side
uniform vec3 u_open_ground_transferred;  // FrameContext::open_ground_transferred
#endif

#if LIGHTS_ON > 0
float ground_visibility(int k, vec3 position) {
#if SHADOWS
    vec4 p = u_light_matrix[k] * vec4(position, 1.0);
    vec2 uv = p.xy / p.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        return 1.0;
    }
    return textureLod(u_ground_visibility, vec3(uv, float(u_light_layer[k])), 0.0).r;
#else
    return 1.0;
#endif
}
#endif

#if TRANSFER
// The transfer's irradiance at the ground point xz. Beyond the grid the clamped texture would
// hold the edge's occlusion out to the plane's edge; there the objects' effect falls off as a
// compact occluder's does, with the cube of the distance (its solid angle as 1 / r^2, its
// cosine at the receiver as 1 / r), towards the open ground's.
vec3 ground_transferred(vec2 xz) {
    vec2 uv = (xz - u_ground_transfer_rect.xy) * u_ground_transfer_rect.z;
    vec3 edge = textureLod(u_ground_transfer, uv, 0.0).rgb;
    float outside = 2.0 * max(abs(uv.x - 0.5), abs(uv.y - 0.5));  // 1 on the grid's edge
    return outside <= 1.0 ? edge
                          : u_open_ground_transferred +
                                (edge - u_open_ground_transferred) / (outside * outside * outside);
}
#endif

// The ground is Lambertian (docs/design.md section 7). Its irradiance E at `position` (on the
// plane), and E_open, what it would be without the objects (their shadows and occlusion gone,
// the plane's own horizon still hiding the lights below it), which the shadow catcher compares
// E with; each with the thesis model's attenuation (1 under the hdr model).
void ground_irradiance(vec3 position, out vec3 E, out float attenuation, out vec3 E_open,
                       out float open_attenuation) {
    E_open = u_flat_irradiance[0];
#if TRANSFER
    E = E_open + ground_transferred(position.xz);
    E_open += u_open_ground_transferred;
#else
    E = E_open;
#endif
    attenuation = u_attenuation_base;
    open_attenuation = u_attenuation_base;
#if LIGHTS_ON > 0
    for (int k = 0; k < LIGHTS_ON; ++k) {
        // The ground's own plane hides a light below its horizon from its top (the true
        // irradiance there is 0, cos < 0), shadows on or off: visibility 0, so that none of the
        // light's SH is left, whose truncated clamped cosine still reaches above the horizon
        // (order 3, 5 degrees below: 0.05 of the light's facing irradiance, f(t) = 1/4 + t/2 +
        // 5/32 (3 t^2 - 1) at t = -0.087; Ramamoorthi and Hanrahan 2001, eq. 8).
        bool below_horizon = u_light_direction[k].y < 0.0;
        float v = below_horizon ? 0.0 : ground_visibility(k, position);
        E -= (1.0 - v) * u_flat_irradiance[k + 1];
        attenuation -= (1.0 - v) * u_light_share[k];
        if (below_horizon) {
            E_open -= u_flat_irradiance[k + 1];
            open_attenuation -= u_light_share[k];
        }
    }
#endif
}
#endif
