// View-space normal codecs for the `normals` axis (Sunet 2018, §5.6). Reads the `normals` axis: only
// templates whose manifest entry lists it may include this file. View-space normals of visible surfaces
// face the camera, i.e. mostly +z.

// Normalise without producing NaN: a zero vector becomes the camera-facing normal. Divided by its largest
// component first, so that no threshold depends on the vector's length: the cross product of two position
// derivatives is a squared pixel footprint, 1e-8 of a scene unit squared in a scene modelled in hectometres,
// and a fixed cut-off there would replace every derived normal (docs/scale.md).
vec3 ao_safe_normalize(vec3 v) {
    float m = max(abs(v.x), max(abs(v.y), abs(v.z)));
    if (!(m > 0.0) || isinf(m)) {
        return vec3(0.0, 0.0, 1.0);
    }
    vec3 u = v / m;
    return u * inversesqrt(dot(u, u));
}

#if defined(AO_NORMALS_RGB8)

vec4 ao_encode_normal(vec3 n) {
    return vec4(n * 0.5 + 0.5, 0.0);
}

vec3 ao_decode_normal(vec4 e) {
    return ao_safe_normalize(e.xyz * 2.0 - 1.0);
}

#elif defined(AO_NORMALS_RG8)

// z is rebuilt as +sqrt(1 - x^2 - y^2): the sign is lost, so grazing surfaces whose view normal points
// slightly away from the camera (possible under perspective) come back mirrored to z >= 0.
vec4 ao_encode_normal(vec3 n) {
    return vec4(n.xy * 0.5 + 0.5, 0.0, 0.0);
}

vec3 ao_decode_normal(vec4 e) {
    vec2 xy = e.xy * 2.0 - 1.0;
    return ao_safe_normalize(vec3(xy, sqrt(max(0.0, 1.0 - dot(xy, xy)))));
}

#elif defined(AO_NORMALS_OCT16)

// Octahedral encoding (Cigolle et al. 2014) in an RG8 unorm target, 2 x 8 bits. Unlike rg8 it keeps the
// full sphere: the normal is projected onto the octahedron |x| + |y| + |z| = 1 and the z < 0 half is folded
// over the diagonals of the unit square.
vec2 ao_sign_not_zero(vec2 v) {
    return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

vec4 ao_encode_normal(vec3 n) {
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if (n.z < 0.0) {
        p = (1.0 - abs(p.yx)) * ao_sign_not_zero(p);
    }
    return vec4(p * 0.5 + 0.5, 0.0, 0.0);
}

vec3 ao_decode_normal(vec4 e) {
    vec2 p = e.xy * 2.0 - 1.0;
    vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    // For the folded half, -n.z is exactly how far each of x, y was pushed away from zero.
    n.xy -= max(-n.z, 0.0) * ao_sign_not_zero(n.xy);
    return ao_safe_normalize(n);
}

#elif defined(AO_NORMALS_DEPTH)

// No normal buffer: the face normal from screen-space derivatives of the view position. The winding of
// cross(dFdx, dFdy) depends on the API's window y direction, so orient it toward the camera (at the origin)
// instead. Derivatives need uniform control flow: call before any early-out. Pixels on a depth edge get
// the normal of a plane spanning both surfaces (one-sided differences).
vec3 ao_normal_from_position(vec3 p) {
    vec3 n = ao_safe_normalize(cross(dFdx(p), dFdy(p)));
    return dot(n, p) > 0.0 ? -n : n;
}

#else
#error "aovar: common/normals.glsl needs the normals axis in `reads`"
#endif
