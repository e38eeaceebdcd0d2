/work/main/nostd-check/target/debug/deps/hfcast_nostd_check-7a01407f7562559a.d: src/lib.rs

/work/main/nostd-check/target/debug/deps/libhfcast_nostd_check-7a01407f7562559a.rlib: src/lib.rs

/work/main/nostd-check/target/debug/deps/libhfcast_nostd_check-7a01407f7562559a.rmeta: src/lib.rs

src/lib.rs:
