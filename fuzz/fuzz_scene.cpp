// libFuzzer target: scene building, a coarse solve, moves, material changes,
// objects added and removed, and incremental updates, all driven by the fuzzer's bytes. A
// finding is a sanitizer report, a crash, an exception the API does not document, a hang
// (-timeout) or a non-finite or negative radiance in the output.
//
// The bytes are read as a small program: settings first, then objects (vertices on a coarse
// lattice so coincident, coplanar and degenerate polygons come up often; now and then a
// special value such as NaN, inf or 1e30), then a list of operations. Sizes are capped so a
// run stays in the milliseconds: at most 6 objects of 8 polygons of up to 8 corners, and up
// to 2 warped sheets of at most 6 x 6 quads (warped_sheet), moved by turns of any angle.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include "radiosity/solver.h"

using namespace radiosity;

namespace {

// Reads the input front to back; past the end every read gives 0, so any prefix of a valid
// input is valid too (libFuzzer shrinks inputs by cutting them).
class Bytes {
public:
    Bytes(const uint8_t* d, size_t n) : d_(d), n_(n) {}
    uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
    int below(int n) { return n <= 1 ? 0 : int(u8() % n); }
    bool flag() { return u8() & 1; }
    bool done() const { return i_ >= n_; }
    // One of a few values (so fuzzed settings stay in the range where a run is fast).
    template <class T, size_t N>
    T pick(const T (&v)[N]) { return v[below(int(N))]; }
    // A coordinate on a lattice of 1/4 steps in [-4, 4), or rarely a special value.
    double coord() {
        uint8_t b = u8();
        if (b >= 250) {
            static const double special[] = {std::nan(""), std::numeric_limits<double>::infinity(), 1e30, -1e-30,
                                             1e12, 4.0 + 1e-9};
            return special[b - 250];
        }
        return (int(b % 32) - 16) * 0.25;
    }

private:
    const uint8_t* d_;
    size_t n_, i_ = 0;
};

[[noreturn]] void finding(const char* what, int object, double value) {
    std::fprintf(stderr, "fuzz_scene finding: %s (object %d, value %g)\n", what, object, value);
    std::abort();
}

// Every corner value finite and non-negative (the invariant for any input).
void check_output(const Solver& s) {
    for (size_t o = 0; o < s.scene().objects().size(); ++o) {
        std::vector<float> c = s.corner_radiance(int(o));
        if (c.size() != 3 * s.scene().objects()[o].corner_count()) finding("corner array has the wrong size", int(o), c.size());
        for (float v : c) {
            if (!std::isfinite(v)) finding("non-finite radiance", int(o), v);
            if (v < 0) finding("negative radiance", int(o), v);
        }
    }
    if (!std::isfinite(s.stats().residual)) finding("non-finite residual", -1, s.stats().residual);
}

Rgb colour(Bytes& in, bool emission) {
    static const double emit[] = {0.0, 0.0, 0.0, 1.0, 10.0, 1e-6, 1e6, 1e30, -1.0, 1e31};
    static const double refl[] = {0.0, 0.3, 0.5, 0.8, 0.95, 0.999, 1.0, -0.1};
    if (emission) return {in.pick(emit), in.pick(emit), in.pick(emit)};
    return {in.pick(refl), in.pick(refl), in.pick(refl)};
}

ObjectDesc object(Bytes& in, int index, int clusters) {
    ObjectDesc o;
    o.name = "obj" + std::to_string(index);
    o.cluster = in.below(clusters + 2) - 1;  // -1, a valid cluster, or one past the end
    // A box-like offset so objects spread out, then lattice vertices.
    const double scale = in.flag() ? 1.0 : (in.flag() ? 1e-3 : 1e3);
    const Vec3 at{in.coord(), in.coord(), in.coord()};
    const int nv = in.below(13);
    for (int v = 0; v < nv; ++v) o.vertices.push_back((Vec3{in.coord(), in.coord(), in.coord()} + at) * scale);
    const int np = in.below(9);
    for (int p = 0; p < np; ++p) {
        const int n = 1 + in.below(8);  // 1..2 corners are invalid: the API must say so
        o.loop_starts.push_back(int32_t(o.corner_verts.size()));
        o.loop_totals.push_back(n);
        for (int k = 0; k < n; ++k) o.corner_verts.push_back(in.below(nv + 1));  // nv: out of range
        o.reflectance.push_back(colour(in, false));
        o.emission.push_back(colour(in, true));
        o.two_sided.push_back(in.u8() % 4 != 0);
    }
    if (in.u8() == 255) o.two_sided.push_back(1);  // wrong length, rarely
    return o;
}

// A rigid move (rotation about a lattice axis by a multiple of 15 degrees plus a lattice
// translation), or rarely a far jump or a matrix the API must reject.
std::array<double, 16> matrix(Bytes& in) {
    const double a = in.below(24) * 15.0 * 3.14159265358979323846 / 180.0;
    const int axis = in.below(3);
    const double c = std::cos(a), s = std::sin(a);
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    R[i * 3 + i] = c, R[i * 3 + j] = -s, R[j * 3 + i] = s, R[j * 3 + j] = c;
    static const double far[] = {0.0, 0.0, 1.0, 1e6, -1e6, 1e15};
    Vec3 t{in.coord() + in.pick(far), in.coord(), in.coord()};
    std::array<double, 16> m = {R[0], R[1], R[2], t.x, R[3], R[4], R[5], t.y, R[6], R[7], R[8], t.z, 0, 0, 0, 1};
    switch (in.below(16)) {
        case 0: m[in.below(16)] = std::nan(""); break;  // rejected
        case 1: m[0] *= 2; break;                         // scale: rejected
        case 2: m[0] = -m[0], m[1] = -m[1], m[2] = -m[2]; break;  // mirror: rejected
        case 3: m[12] = 1; break;                         // not affine: rejected
        default: break;
    }
    return m;
}

// A rotation by any angle about any axis (Rodrigues), as a turn dragged in Blender gives:
// its matrix is rigid only to rounding, and turned quads are planar only to rounding.
void any_rotation(Bytes& in, double R[9]) {
    Vec3 a{double(int(in.u8()) - 128), double(int(in.u8()) - 128), double(int(in.u8()) - 128)};
    const double l = length(a);
    a = l > 0 ? a / l : Vec3{0, 0, 1};
    const double t = (in.u8() * 256 + in.u8()) * (2 * 3.14159265358979323846 / 65536.0);
    const double c = std::cos(t), s = std::sin(t), k = 1 - c;
    const double m[9] = {c + a.x * a.x * k,       a.x * a.y * k - a.z * s, a.x * a.z * k + a.y * s,
                         a.y * a.x * k + a.z * s, c + a.y * a.y * k,       a.y * a.z * k - a.x * s,
                         a.z * a.x * k - a.y * s, a.z * a.y * k + a.x * s, c + a.z * a.z * k};
    for (int i = 0; i < 9; ++i) R[i] = m[i];
}

// A move with a turn by any angle about any axis through the object's neighbourhood, and a
// lattice translation: the object can end inside a wall or another object.
std::array<double, 16> turned_matrix(Bytes& in) {
    double R[9];
    any_rotation(in, R);
    const Vec3 t{in.coord(), in.coord(), in.coord()};
    return {R[0], R[1], R[2], t.x, R[3], R[4], R[5], t.y, R[6], R[7], R[8], t.z, 0, 0, 0, 1};
}

// A gridded sheet of quads as Bevel and Subdivision Surface leave them: each vertex lifted off
// the sheet by a warp from a rounding error up to far beyond the hierarchy's planarity
// tolerance, sometimes bulged into a cushion, in any orientation. Its quads are warped and,
// where the warp is large, concave or bow-tied; planes through neighbouring points cross them
// up to four times.
ObjectDesc warped_sheet(Bytes& in, int index, int clusters) {
    ObjectDesc o;
    o.name = "sheet" + std::to_string(index);
    o.cluster = in.below(clusters + 1) - 1;
    static const double warps[] = {0.0, 1e-12, 1e-9, 1e-6, 2e-5, 1e-4, 3e-4, 1e-2, 0.3};
    const double warp = in.pick(warps);
    const double bulge = in.flag() ? 0.25 * in.below(5) : 0.0;
    const int n = 1 + in.below(6);
    const double size = 0.5 + 0.25 * in.below(12);
    double R[9];
    any_rotation(in, R);
    const Vec3 at{in.coord(), in.coord(), in.coord()};
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = 2.0 * i / n - 1, v = 2.0 * j / n - 1;
            const double lift = warp * (size / n) * (int(in.u8()) - 128) / 128.0 + bulge * (1 - u * u) * (1 - v * v);
            const Vec3 p{u * size, v * size, lift};
            o.vertices.push_back(Vec3{R[0] * p.x + R[1] * p.y + R[2] * p.z, R[3] * p.x + R[4] * p.y + R[5] * p.z,
                                      R[6] * p.x + R[7] * p.y + R[8] * p.z} + at);
        }
    const Rgb rho = colour(in, false), e = colour(in, true);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i;
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            o.corner_verts.insert(o.corner_verts.end(), {a, a + 1, a + n + 2, a + n + 1});
            o.reflectance.push_back(rho);
            o.emission.push_back(i == 0 && j == 0 ? e : Rgb{});
            o.two_sided.push_back(in.u8() % 4 != 0);
        }
    return o;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Bytes in(data, size);

    // Coarse settings only: a single solve must take milliseconds.
    Settings st;
    static const double eps[] = {1e9, 1.0, 0.5, 0.2, 0.1};
    static const double min_area[] = {1e-2, 1e-3, 1e-4, 0.0};
    st.error_threshold = in.pick(eps);
    st.min_area_fraction = in.pick(min_area);
    st.max_elements = 200 + 100 * in.below(20);
    st.max_links = 500 + 500 * in.below(20);
    st.use_clustering = in.u8() % 4 != 0;
    st.progressive_refinement = in.flag();
    st.rays_per_link = 1 + in.below(4);
    st.max_iterations = 1 + in.below(200);
    st.max_refine_rounds = in.below(3);
    st.closure_rays = in.below(9);
    st.threads = 1;  // deterministic: a finding must reproduce from its input alone
    st.seed = in.u8();

    SceneDesc scene;
    const int clusters = in.below(3);
    for (int c = 0; c < clusters; ++c) {
        try {
            scene.add_cluster("c" + std::to_string(c), in.below(c + 2) - 1);
        } catch (const InputError&) {
        }
    }
    const int objects = in.below(7);
    for (int i = 0; i < objects; ++i) {
        try {
            scene.add_object(object(in, i, int(scene.clusters().size())));
        } catch (const InputError&) {
            // Bad input is rejected with a message; the scene goes on without it.
        }
    }

    const int sheets = in.below(3);
    for (int i = 0; i < sheets; ++i) {
        try {
            scene.add_object(warped_sheet(in, objects + i, int(scene.clusters().size())));
        } catch (const InputError&) {
        }
    }

    // The final gather (the corner output) half the time, its gathers shared or not. Read after
    // the scene, so that an input keeps its scene.
    if (in.flag()) {
        static const int rays[] = {4, 8, 16};
        static const double share[] = {0.0, 0.3, 1.0};
        st.gather_rays = in.pick(rays);
        st.gather_min_rays = 1 + in.below(2);
        st.gather_share = in.pick(share);
    }
    Solver solver(std::move(scene), st);  // the settings above always validate
    solver.solve();
    check_output(solver);

    const int ops = in.below(5);
    for (int k = 0; k < ops && !in.done(); ++k) {
        const int n_objects = int(solver.scene().objects().size());
        const int obj = in.below(n_objects + 1);  // n_objects: unknown object (or a removed one)
        try {
            switch (in.below(8)) {
                case 6: {
                    const std::array<double, 16> m = turned_matrix(in);
                    solver.move_object(obj, m);
                    break;
                }
                case 7:
                    solver.add_object(warped_sheet(in, n_objects, int(solver.scene().clusters().size())));
                    break;
                case 4:
                    solver.remove_object(obj);
                    break;
                case 5:
                    solver.add_object(object(in, n_objects, int(solver.scene().clusters().size())));
                    break;
                case 0:
                case 1: {
                    const std::array<double, 16> m = matrix(in);
                    solver.move_object(obj, m);
                    break;
                }
                case 2: {
                    const int np = obj < n_objects ? int(solver.scene().objects()[obj].polygon_count()) : 1;
                    std::vector<Rgb> v(in.flag() ? 1 : size_t(np), colour(in, true));
                    solver.set_emission(obj, v);
                    break;
                }
                default: {
                    const int np = obj < n_objects ? int(solver.scene().objects()[obj].polygon_count()) : 1;
                    std::vector<Rgb> v(in.flag() ? 1 : size_t(np), colour(in, false));
                    solver.set_reflectance(obj, v);
                    break;
                }
            }
        } catch (const InputError&) {
            // Rejected: the kept solution must be untouched and still valid.
        }
        if (in.flag()) {
            solver.update();
            check_output(solver);
        }
    }
    solver.update();
    check_output(solver);
    // Point queries on the first polygon of each object, inside and far outside it.
    for (int o = 0; o < int(solver.scene().objects().size()); ++o) {
        if (solver.scene().objects()[o].polygon_count() == 0) continue;  // also removed objects
        try {
            Rgb r = solver.radiance_at(o, 0, Vec3{in.coord(), in.coord(), in.coord()});
            if (!finite(r)) finding("non-finite radiance_at", o, r.g);
        } catch (const std::out_of_range&) {
            // Documented: the polygon was skipped (zero area), so there is no such face.
        } catch (const InputError&) {
            // Documented: a non-finite query point is rejected.
        }
    }
    return 0;
}
