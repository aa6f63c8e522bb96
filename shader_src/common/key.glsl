// SAO's depth key (McGuire et al. 2012, §2.3): the AO pass packs linear depth next to AO into an rgba8 target,
// (A, key_hi, key_lo), so its bilateral passes read one texel for both instead of the depth buffer too.
// 16 bits in two 8-bit unorm channels: hi holds floor(t * 255.999) / 255 (exactly representable), lo the
// fraction left over. The seed keys z / z_min linearly (z_min a chosen "farthest sharp plane"); with the far
// plane in that role a linear key spends its steps on the distance: far / 65536 per step, 15 units at
// far = 1e6, so everything nearer than that shares key 0 and the blurs' relative depth weight (which divides
// by z) breaks (`aovar stress`, case far-1e6: NaN at every such pixel). Here t = log2(z / near) / log2(far /
// near) instead: a constant relative step of (far / near)^(1 / 65536), 0.025 % at far / near = 1e7. The
// ratio is capped at 2^40 so that an infinite far plane keeps that resolution; t = 1 (the far plane and
// beyond) unpacks to the far plane itself, so background tests see exactly what the G-buffer held.
#include "common/frame.glsl"

float ao_key_range() {
    return clamp(log2(frame.clip.y / frame.clip.x), 1.0, 40.0);
}

vec2 ao_pack_key(float z) {
    float t = clamp(log2(max(z, frame.clip.x) / frame.clip.x) / ao_key_range(), 0.0, 1.0) * 255.999;
    float hi = floor(t);
    return vec2(hi / 255.0, t - hi);
}

float ao_unpack_key(vec2 key) {
    float t = (floor(key.x * 255.0 + 0.5) + key.y) / 255.999;
    return t >= 0.99999 ? frame.clip.y : frame.clip.x * exp2(t * ao_key_range());
}
