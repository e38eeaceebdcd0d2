// Mirror of core/src/ray.rs: queries, hits, traces, ray classes.

// `Query<f32>`: `origin + t * dir` for t in [t_min, t_max] (validated by the caller).
struct Query {
    origin: vec3<f32>,
    dir: vec3<f32>,
    t_min: f32,
    t_max: f32,
}

// `Query::at`.
fn query_at(q: Query, t: f32) -> vec3<f32> {
    return vec3<f32>(q.origin.x + t * q.dir.x, q.origin.y + t * q.dir.y, q.origin.z + t * q.dir.z);
}

// `RayClass::of`.
fn ray_class_of(dx: f32, dy: f32) -> u32 {
    let zero: bool = dx == 0.0 && dy == 0.0;
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
    t: f32,
    point: vec3<f32>,
    cell: vec2<u32>,
    normal: vec3<f32>,
    flags: u32,
}

// `Trace<f32>`; `has_hit` stands for `hit.is_some()`.
struct Trace {
    has_hit: bool,
    hit: Hit,
    fetches: u32,
    clearance: f32,
    flags: u32,
}

fn hit_none() -> Hit { return Hit(0.0, vec3<f32>(0.0), vec2<u32>(0u), vec3<f32>(0.0), 0u); }

// `Trace::MISS` with the given cost and clearance.
fn trace_miss(fetches: u32, clearance: f32) -> Trace {
    return Trace(false, hit_none(), fetches, clearance, 0u);
}

fn trace_hit(hit: Hit, fetches: u32, clearance: f32) -> Trace {
    return Trace(true, hit, fetches, clearance, 0u);
}
