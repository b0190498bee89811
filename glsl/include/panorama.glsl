// Where a world direction lies in an equirectangular map (`environment::direction_at`'s layout: x the azimuth
// from −180° to 180°, 0 along +z and 90° along +x; y the elevation from +90° at the top), for the background's
// map and the environment light the surface reflects. Needs PI (interface.glsl).

// The texture coordinates of the unit direction d in the map turned by `turn` radians about +y (the texel at
// azimuth φ shows at φ + turn).
vec2 panorama_uv(vec3 d, float turn) {
    float azimuth = atan(d.x, d.z) - turn;
    float elevation = asin(clamp(d.y, -1.0, 1.0));
    return vec2(azimuth / (2.0 * PI) + 0.5, 0.5 - elevation / PI);
}
