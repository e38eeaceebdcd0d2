// A C++ program using an installed hfcast (scripts/install.sh): it makes a small
// field of hills, bakes its maximum mipmap, traces a fan of rays with the maximum
// mipmap march and with the exact grid march, and checks that they agree (the maximum
// mipmap march is exact: it must find the same hit). Exits non-zero on any mismatch.
//
// Build against the installed tree only (see README.md, "Install"):
//   c++ main.cpp $(pkg-config --cflags --libs hfcast)
//   c++ main.cpp $(pkg-config --static --cflags --libs hfcast-static)
//   cmake -S . -B build -DCMAKE_PREFIX_PATH=PREFIX && cmake --build build
#include <hfcast.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace {

// Says what went wrong and returns false when `r` is not HF_OK.
bool ok(hf_result r, const char *what) {
    if (r == HF_OK) return true;
    char msg[128];
    size_t len = 0;
    if (hf_error_message(r, msg, sizeof msg, &len) != HF_OK) std::snprintf(msg, sizeof msg, "?");
    std::fprintf(stderr, "%s failed: %u (%s)\n", what, static_cast<unsigned>(r), msg);
    return false;
}

struct FieldDeleter {
    void operator()(hf_field *f) const { hf_field_destroy(f); }
};
using Field = std::unique_ptr<hf_field, FieldDeleter>;

}  // namespace

int main() {
    // The library must be the version of the header this program was compiled with.
    uint32_t major = 0, minor = 0, patch = 0;
    if (!ok(hf_version(&major, &minor, &patch), "hf_version")) return 1;
    std::printf("hfcast %u.%u.%u (header %s)\n", major, minor, patch, HFCAST_VERSION_STRING);
    if (major != HFCAST_VERSION_MAJOR || minor != HFCAST_VERSION_MINOR) {
        std::fprintf(stderr, "library and header versions differ\n");
        return 1;
    }

    // 48 x 32 samples of rolling hills, 2 to 10 grid units high.
    const uint32_t w = 48, h = 32;
    std::vector<float> heights(w * h);
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++)
            heights[j * w + i] = 6.0f + 3.0f * std::sin(0.31f * i) * std::cos(0.23f * j) +
                                 std::sin(0.9f * i + 0.7f * j);
    hf_field *raw = nullptr;
    if (!ok(hf_field_create_f32(heights.data(), heights.size(), w, h, w, &raw),
            "hf_field_create_f32"))
        return 1;
    Field field(raw);

    size_t pyramid_len = 0;
    if (!ok(hf_map_len(HF_METHOD_MAXMIP, w, h, nullptr, &pyramid_len), "hf_map_len")) return 1;
    std::vector<float> pyramid(pyramid_len);
    if (!ok(hf_bake(HF_METHOD_MAXMIP, field.get(), nullptr, pyramid.data(), pyramid.size()),
            "hf_bake"))
        return 1;

    // A fan of rays from a viewpoint above one corner towards points across the field,
    // and one ray upwards that must miss.
    std::vector<hf_ray> rays;
    for (int k = 0; k < 8; k++) {
        const float tx = 4.0f + 5.5f * k, ty = 2.0f + 3.7f * k;
        hf_ray r = {{-6.0f, -4.0f, 30.0f}, {tx + 6.0f, ty + 4.0f, -30.0f}, 0.0f, INFINITY};
        rays.push_back(r);
    }
    const hf_ray up = {{10.0f, 10.0f, 12.0f}, {0.3f, 0.2f, 1.0f}, 0.0f, INFINITY};
    rays.push_back(up);

    // Both traces on the triangle surface (the default options; nullptr means the same).
    hf_trace_options options;
    if (!ok(hf_trace_options_default(&options), "hf_trace_options_default")) return 1;
    options.surface = HF_SURFACE_TRIANGLES;

    int mismatches = 0, hits = 0;
    for (size_t k = 0; k < rays.size(); k++) {
        hf_hit exact, maxmip;
        if (!ok(hf_trace(field.get(), HF_METHOD_EXACT, nullptr, 0, &options, &rays[k], &exact),
                "hf_trace (exact)") ||
            !ok(hf_trace(field.get(), HF_METHOD_MAXMIP, pyramid.data(), pyramid.size(), &options,
                         &rays[k], &maxmip),
                "hf_trace (maxmip)"))
            return 1;
        const bool same = exact.hit == maxmip.hit && exact.cell[0] == maxmip.cell[0] &&
                          exact.cell[1] == maxmip.cell[1] &&
                          std::fabs(exact.t - maxmip.t) <= 1e-5f * std::fmax(1.0f, exact.t);
        hits += exact.hit ? 1 : 0;
        if (!same) mismatches++;
        if (exact.hit)
            std::printf("ray %zu: hit t = %.5f at (%.3f, %.3f, %.3f) in cell (%u, %u); "
                        "maxmip t = %.5f, %u fetches against %u %s\n",
                        k, exact.t, exact.point[0], exact.point[1], exact.point[2],
                        exact.cell[0], exact.cell[1], maxmip.t, maxmip.fetches, exact.fetches,
                        same ? "ok" : "MISMATCH");
        else
            std::printf("ray %zu: miss (maxmip: %s) %s\n", k, maxmip.hit ? "hit" : "miss",
                        same ? "ok" : "MISMATCH");
    }
    // Every fan ray points at the field from above it: each must hit; the last misses.
    if (hits != static_cast<int>(rays.size()) - 1) {
        std::fprintf(stderr, "%d hits, expected %zu\n", hits, rays.size() - 1);
        return 1;
    }
    std::printf("%zu rays, %d hits, %d mismatches\n", rays.size(), hits, mismatches);
    return mismatches == 0 ? 0 : 1;
}
