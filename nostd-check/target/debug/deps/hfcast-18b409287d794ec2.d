/work/main/nostd-check/target/debug/deps/hfcast-18b409287d794ec2.d: /work/main/core/src/lib.rs /work/main/core/src/bake.rs /work/main/core/src/buffer.rs /work/main/core/src/camera.rs /work/main/core/src/condition.rs /work/main/core/src/dda.rs /work/main/core/src/field.rs /work/main/core/src/hybrid.rs /work/main/core/src/judge.rs /work/main/core/src/ktx2.rs /work/main/core/src/mapdesc.rs /work/main/core/src/march.rs /work/main/core/src/math.rs /work/main/core/src/multires.rs /work/main/core/src/ray.rs /work/main/core/src/rayset.rs /work/main/core/src/rng.rs /work/main/core/src/scene.rs /work/main/core/src/simd.rs /work/main/core/src/surface.rs /work/main/core/src/world.rs

/work/main/nostd-check/target/debug/deps/libhfcast-18b409287d794ec2.rlib: /work/main/core/src/lib.rs /work/main/core/src/bake.rs /work/main/core/src/buffer.rs /work/main/core/src/camera.rs /work/main/core/src/condition.rs /work/main/core/src/dda.rs /work/main/core/src/field.rs /work/main/core/src/hybrid.rs /work/main/core/src/judge.rs /work/main/core/src/ktx2.rs /work/main/core/src/mapdesc.rs /work/main/core/src/march.rs /work/main/core/src/math.rs /work/main/core/src/multires.rs /work/main/core/src/ray.rs /work/main/core/src/rayset.rs /work/main/core/src/rng.rs /work/main/core/src/scene.rs /work/main/core/src/simd.rs /work/main/core/src/surface.rs /work/main/core/src/world.rs

/work/main/nostd-check/target/debug/deps/libhfcast-18b409287d794ec2.rmeta: /work/main/core/src/lib.rs /work/main/core/src/bake.rs /work/main/core/src/buffer.rs /work/main/core/src/camera.rs /work/main/core/src/condition.rs /work/main/core/src/dda.rs /work/main/core/src/field.rs /work/main/core/src/hybrid.rs /work/main/core/src/judge.rs /work/main/core/src/ktx2.rs /work/main/core/src/mapdesc.rs /work/main/core/src/march.rs /work/main/core/src/math.rs /work/main/core/src/multires.rs /work/main/core/src/ray.rs /work/main/core/src/rayset.rs /work/main/core/src/rng.rs /work/main/core/src/scene.rs /work/main/core/src/simd.rs /work/main/core/src/surface.rs /work/main/core/src/world.rs

/work/main/core/src/lib.rs:
/work/main/core/src/bake.rs:
/work/main/core/src/buffer.rs:
/work/main/core/src/camera.rs:
/work/main/core/src/condition.rs:
/work/main/core/src/dda.rs:
/work/main/core/src/field.rs:
/work/main/core/src/hybrid.rs:
/work/main/core/src/judge.rs:
/work/main/core/src/ktx2.rs:
/work/main/core/src/mapdesc.rs:
/work/main/core/src/march.rs:
/work/main/core/src/math.rs:
/work/main/core/src/multires.rs:
/work/main/core/src/ray.rs:
/work/main/core/src/rayset.rs:
/work/main/core/src/rng.rs:
/work/main/core/src/scene.rs:
/work/main/core/src/simd.rs:
/work/main/core/src/surface.rs:
/work/main/core/src/world.rs:

# env-dep:CARGO_PKG_VERSION=0.2.0
