// Generated from shaders/wgsl/ray.wgsl by shaders/src/translate.rs: do not edit.
// Regenerate with: HFCAST_BLESS=1 cargo test -p hfcast-shaders --test validate
// Mirror of core/src/ray.rs: queries, hits, traces, ray classes.

// `Query<f32>`: `origin + t * dir` for t in [t_min, t_max] (validated by the caller).
struct Query {
    vec3 origin;
    vec3 dir;
    float t_min;
    float t_max;
};

// `Query::at`.
vec3 query_at(Query q, float t) {
    return vec3(q.origin.x + t * q.dir.x, q.origin.y + t * q.dir.y, q.origin.z + t * q.dir.z);
}

// `RayClass::of`.
uint ray_class_of(float dx, float dy) {
    bool zero = dx == 0.0 && dy == 0.0;
    if (dx >= abs(dy) && !zero) {
        return HF_RAY_CLASS_X_POS;
    } else if (-dx >= abs(dy) && !zero) {
        return HF_RAY_CLASS_X_NEG;
    } else if (dy > abs(dx)) {
        return HF_RAY_CLASS_Y_POS;
    }
    return HF_RAY_CLASS_Y_NEG;
}

// `Hit<f32>`.
struct Hit {
    float t;
    vec3 point;
    uvec2 cell;
    vec3 normal;
    uint flags;
};

// `Trace<f32>`; `has_hit` stands for `hit.is_some()`.
struct Trace {
    bool has_hit;
    Hit hit;
    uint fetches;
    float clearance;
    uint flags;
};

Hit hit_none() { return Hit(0.0, vec3(0.0), uvec2(0u), vec3(0.0), 0u); }

// `Trace::MISS` with the given cost and clearance.
Trace trace_miss(uint fetches, float clearance) {
    return Trace(false, hit_none(), fetches, clearance, 0u);
}

Trace trace_hit(Hit hit, uint fetches, float clearance) {
    return Trace(true, hit, fetches, clearance, 0u);
}
