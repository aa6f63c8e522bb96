// SAO's depth key (seed 003 §2.3): the AO pass packs linear depth next to AO into an rgba8 target,
// (A, key_hi, key_lo), so its bilateral passes read one texel for both instead of the depth buffer too.
// key = z / far in [0, 1], split into two 8-bit unorm channels: hi holds floor(key * 255.999) / 255
// (exactly representable), lo the fraction left over; 16 bits in all, far / 65536 (e.g. 1 mm at 60 m).
// The seed divides by a chosen "farthest sharp plane" z_min (-200 m); aovar's far plane plays that role.
#include "common/frame.glsl"

vec2 ao_pack_key(float z) {
    float t = clamp(z / frame.clip.y, 0.0, 1.0) * 255.999;
    float hi = floor(t);
    return vec2(hi / 255.0, t - hi);
}

float ao_unpack_key(vec2 key) {
    return (floor(key.x * 255.0 + 0.5) + key.y) / 255.999 * frame.clip.y;
}
