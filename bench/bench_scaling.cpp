// Scaling benchmark: full-bake time, peak memory, elements and links of synthetic
// rooms from ~1k to ~1M input triangles, and the log-log least-squares exponent of each.
//
//   bench_scaling [--quick] [--preset DRAFT|MEDIUM] [--families furniture,subdivided]
//                 [--sizes 1000,4000,...] [--timeout SECONDS] [--max-mb 12000] [--jsonl FILE]
//   bench_scaling --one FAMILY N PRESET [MAX_MB]   (one size, in this process; a JSON line)
//
// Families (all: a 400 x 400 x 250 room of inward faces, a 100 x 100 ceiling light of
// radiance 12 one unit below the ceiling, everything triangulated):
//   furniture  - a k x k grid of boxes standing on the floor, each its own object and cluster,
//                each face 4 x 4 cells (192 triangles a box); ~3/4 of the triangles in boxes,
//                the room's faces subdivided for the rest.
//   subdivided - the same room with 4 boxes, every face subdivided uniformly (r x r cells a room
//                face, r/2 x r/2 a box face), so n grows by subdivision only.
// Each size runs in a fresh process (this binary again, via /proc/self/exe, under `timeout`),
// so the peak memory (VmHWM) is that size's alone, with its data segment limited to --max-mb (the
// machine is shared: a size that needs more fails instead of pushing other work out); a family
// stops at its first size that times out or fails. --quick: 1k and 2k only (for CI; no timing is judged anywhere).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "radiosity/scene.h"
#include "radiosity/settings.h"
#include "radiosity/solver.h"

using namespace radiosity;

namespace {

// Appends a triangulated nu x nv grid over the quad a,b,c,d (counter-clockwise about its front).
void append_tri_grid(ObjectDesc& o, const std::array<Vec3, 4>& q, int nu, int nv, Rgb rho, Rgb emission) {
    const int32_t base = static_cast<int32_t>(o.vertices.size());
    for (int j = 0; j <= nv; ++j) {
        const double v = double(j) / nv;
        for (int i = 0; i <= nu; ++i) {
            const double u = double(i) / nu;
            // Bilinear point on the quad.
            Vec3 p = q[0] * ((1 - u) * (1 - v)) + q[1] * (u * (1 - v)) + q[2] * (u * v) + q[3] * ((1 - u) * v);
            o.vertices.push_back(p);
        }
    }
    auto V = [&](int i, int j) { return base + j * (nu + 1) + i; };
    auto tri = [&](int32_t a, int32_t b, int32_t c) {
        o.loop_starts.push_back(static_cast<int32_t>(o.corner_verts.size()));
        o.loop_totals.push_back(3);
        o.corner_verts.insert(o.corner_verts.end(), {a, b, c});
        o.reflectance.push_back(rho);
        o.emission.push_back(emission);
        o.two_sided.push_back(1);
    };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            tri(V(i, j), V(i + 1, j), V(i + 1, j + 1));
            tri(V(i, j), V(i + 1, j + 1), V(i, j + 1));
        }
}

// The six faces of the box lo..hi, counter-clockwise seen from outside (inward: reversed).
std::array<std::array<Vec3, 4>, 6> box_faces(Vec3 lo, Vec3 hi, bool inward) {
    auto P = [&](int x, int y, int z) { return Vec3{x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z}; };
    std::array<std::array<Vec3, 4>, 6> f = {{
        {P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0)},
        {P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1)},
        {P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1)},
        {P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0)},
        {P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0)},
        {P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1)},
    }};
    if (inward)
        for (auto& q : f) std::swap(q[1], q[3]);
    return f;
}

void add_tri_box(SceneDesc& s, const std::string& name, int cluster, Vec3 lo, Vec3 hi, int n, Rgb rho,
                 bool inward) {
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    for (const auto& q : box_faces(lo, hi, inward)) append_tri_grid(o, q, n, n, rho, Rgb{});
    s.add_object(std::move(o));
}

const Vec3 kRoom{400, 400, 250};

void add_room_and_light(SceneDesc& s, int r) {
    add_tri_box(s, "room", -1, {0, 0, 0}, kRoom, std::max(1, r), Rgb{0.7, 0.7, 0.7}, true);
    ObjectDesc light;
    light.name = "light";
    append_tri_grid(light, {Vec3{150, 150, 249}, Vec3{150, 250, 249}, Vec3{250, 250, 249}, Vec3{250, 150, 249}}, 1,
                    1, Rgb{}, Rgb::all(12.0));  // faces down
    s.add_object(std::move(light));
}

Rgb palette(int i) {
    static const Rgb c[] = {{0.65, 0.12, 0.08}, {0.12, 0.25, 0.6}, {0.5, 0.3, 0.15}, {0.6, 0.6, 0.5}, {0.2, 0.5, 0.2}};
    return c[i % 5];
}

SceneDesc furniture(int64_t n_target) {
    SceneDesc s;
    const int per_box = 6 * 4 * 4 * 2;
    const int k = std::max(1, int(std::lround(std::sqrt(0.75 * double(n_target) / per_box))));
    const int r = std::max(1, int(std::lround(std::sqrt(0.25 * double(n_target) / 12.0))));
    add_room_and_light(s, r);
    const double pitch = 360.0 / k, foot = 0.6 * pitch;
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const double cx = 20 + pitch * (i + 0.5), cy = 20 + pitch * (j + 0.5);
            const double h = 20 + 60 * std::fmod(0.618034 * (i * 7 + j * 13 + 1), 1.0);
            const std::string name = "box" + std::to_string(j * k + i);
            const int cl = s.add_cluster(name);
            add_tri_box(s, name, cl, {cx - foot / 2, cy - foot / 2, 0}, {cx + foot / 2, cy + foot / 2, h}, 4,
                        palette(i + j), false);
        }
    return s;
}

SceneDesc subdivided(int64_t n_target) {
    SceneDesc s;
    // room 12 r^2 + 4 boxes x 12 (r/2)^2 = 24 r^2 triangles.
    const int r = std::max(2, int(std::lround(std::sqrt(double(n_target) / 24.0))));
    add_room_and_light(s, r);
    const std::array<std::array<double, 5>, 4> boxes = {{{60, 60, 160, 140, 100},
                                                         {230, 60, 340, 130, 70},
                                                         {70, 240, 150, 340, 180},
                                                         {240, 250, 330, 340, 45}}};
    for (int b = 0; b < 4; ++b) {
        const auto& B = boxes[b];
        const std::string name = "piece" + std::to_string(b);
        const int cl = s.add_cluster(name);
        add_tri_box(s, name, cl, {B[0], B[1], 0}, {B[2], B[3], B[4]}, std::max(1, r / 2), palette(b), false);
    }
    return s;
}

long status_kb(const char* key) {
    std::ifstream f("/proc/self/status");
    std::string line;
    const size_t n = std::strlen(key);
    while (std::getline(f, line))
        if (line.compare(0, n, key) == 0) return std::atol(line.c_str() + n + 1);
    return -1;
}

int run_one(const std::string& family, int64_t n, const std::string& preset, long max_mb) {
    if (max_mb > 0) {  // a shared machine: fail this size (bad_alloc) rather than push others out
        rlimit lim{};
        lim.rlim_cur = lim.rlim_max = static_cast<rlim_t>(max_mb) << 20;
        setrlimit(RLIMIT_DATA, &lim);
    }
    using clk = std::chrono::steady_clock;
    auto t0 = clk::now();
    SceneDesc scene = family == "furniture" ? furniture(n) : subdivided(n);
    const double t_scene = std::chrono::duration<double>(clk::now() - t0).count();
    const long rss_scene = status_kb("VmHWM:");
    Settings st = Settings::preset(preset);
    auto t1 = clk::now();
    Solver solver(std::move(scene), st);
    solver.solve();
    const double t_bake = std::chrono::duration<double>(clk::now() - t1).count();
    const Stats& s = solver.stats();
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    std::printf(
        "RESULT {\"family\":\"%s\",\"target\":%lld,\"triangles\":%lld,\"objects\":%lld,\"clusters\":%lld,"
        "\"elements\":%lld,\"element_nodes\":%lld,\"links\":%lld,\"cluster_links\":%lld,\"history_links\":%lld,"
        "\"rays\":%lld,\"iterations\":%d,\"capped\":%s,\"seconds\":%.3f,\"seconds_scene\":%.3f,"
        "\"seconds_build\":%.3f,\"seconds_link\":%.3f,\"seconds_solve\":%.3f,\"vmhwm_kb\":%ld,"
        "\"vmhwm_scene_kb\":%ld,\"maxrss_kb\":%ld,\"cpu_seconds\":%.3f}\n",
        family.c_str(), (long long)n, (long long)s.input_surfaces, (long long)s.objects, (long long)s.clusters,
        (long long)s.elements, (long long)s.element_nodes, (long long)s.links, (long long)s.cluster_links,
        (long long)s.history_links, (long long)s.rays, s.iterations, s.capped ? "true" : "false", t_bake, t_scene,
        s.seconds_build, s.seconds_link, s.seconds_solve, status_kb("VmHWM:"), rss_scene, ru.ru_maxrss,
        ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec));
    return 0;
}

// A tiny JSON-ish field reader for our own RESULT lines (numbers and booleans only).
double field(const std::string& line, const std::string& key) {
    const std::string k = "\"" + key + "\":";
    const size_t p = line.find(k);
    if (p == std::string::npos) return NAN;
    const char* v = line.c_str() + p + k.size();
    if (std::strncmp(v, "true", 4) == 0) return 1;
    if (std::strncmp(v, "false", 5) == 0) return 0;
    return std::atof(v);
}

// Least-squares slope of log y against log x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
    const size_t n = x.size();
    if (n < 2) return NAN;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < n; ++i) {
        const double a = std::log(x[i]), b = std::log(y[i]);
        sx += a, sy += b, sxx += a * a, sxy += a * b;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

std::vector<std::string> split(const std::string& s, char c) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, c))
        if (!item.empty()) out.push_back(item);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (!args.empty() && args[0] == "--one") {
        if (args.size() < 4) {
            std::fprintf(stderr, "usage: bench_scaling --one FAMILY N PRESET [MAX_MB]\n");
            return 2;
        }
        try {
            return run_one(args[1], std::atoll(args[2].c_str()), args[3],
                           args.size() > 4 ? std::atol(args[4].c_str()) : 0);
        } catch (const std::bad_alloc&) {
            std::printf("out of memory (the --max-mb limit)\n");
            return 3;
        } catch (const std::exception& e) {  // e.g. Embree's device cannot get memory either
            std::printf("error: %s\n", e.what());
            return 4;
        }
    }
    bool quick = false;
    std::string preset = "DRAFT", jsonl;
    std::vector<std::string> families = {"furniture", "subdivided"};
    std::vector<int64_t> sizes = {1000, 4000, 16000, 64000, 256000, 1000000};
    int timeout = 600;
    long max_mb = 12000;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= args.size()) {
                std::fprintf(stderr, "%s needs a value\n", a.c_str());
                std::exit(2);
            }
            return args[++i];
        };
        if (a == "--quick") quick = true;
        else if (a == "--preset") preset = next();
        else if (a == "--families") families = split(next(), ',');
        else if (a == "--sizes") {
            sizes.clear();
            for (auto& v : split(next(), ',')) sizes.push_back(std::atoll(v.c_str()));
        } else if (a == "--timeout") timeout = std::atoi(next().c_str());
        else if (a == "--max-mb") max_mb = std::atol(next().c_str());
        else if (a == "--jsonl") jsonl = next();
        else {
            std::fprintf(stderr, "unknown argument %s\n", a.c_str());
            return 2;
        }
    }
    // Two sizes are enough to fit an exponent; 4k furniture needs ~3 GB and 20 CPU s: too much for CI.
    if (quick) sizes = {1000, 2000};
    if (!jsonl.empty()) std::ofstream(jsonl, std::ios::trunc);
    char self[4096];
    const ssize_t len = readlink("/proc/self/exe", self, sizeof(self) - 1);
    if (len <= 0) return 1;
    self[len] = 0;

    std::printf("Scaling: preset %s, %d threads available, each size in a fresh process (timeout %d s, data limit %ld MB)\n\n", preset.c_str(),
                (int)sysconf(_SC_NPROCESSORS_ONLN), timeout, max_mb);
    std::printf("| family | target n | triangles | objects | elements | links | cluster links | rays | bake s (wall) | CPU s | peak MB (VmHWM) | scene-only MB |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);
    std::vector<std::string> lines;
    std::map<std::string, std::string> stopped;
    for (const auto& fam : families) {
        for (int64_t n : sizes) {
            const std::string cmd = "timeout " + std::to_string(timeout) + " '" + self + "' --one " + fam + " " +
                                    std::to_string(n) + " " + preset + " " + std::to_string(max_mb) + " 2>&1";
            FILE* p = popen(cmd.c_str(), "r");
            std::string out, result;
            char buf[8192];
            while (p && std::fgets(buf, sizeof(buf), p)) {
                out += buf;
                if (std::strncmp(buf, "RESULT ", 7) == 0) result = buf + 7;
            }
            const int rc = p ? pclose(p) : -1;
            if (result.empty() || rc != 0) {
                const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
                stopped[fam] = "n = " + std::to_string(n) + ": " +
                               (code == 124   ? "timed out after " + std::to_string(timeout) + " s"
                                : code == 3 ? "out of memory: over the " + std::to_string(max_mb) + " MB limit (--max-mb)"
                                            : "failed (exit " + std::to_string(code) + "): " +
                                                  out.substr(out.size() > 300 ? out.size() - 300 : 0));
                std::printf("| %s | %lld | %s | | | | | | | | | |\n", fam.c_str(), (long long)n, stopped[fam].c_str());
                std::fflush(stdout);
                break;
            }
            lines.push_back(result);
            if (!jsonl.empty()) std::ofstream(jsonl, std::ios::app) << result;  // survives a kill
            const std::string& r = result;
            std::printf("| %s | %lld | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f | %.2f | %.0f | %.0f |\n",
                        fam.c_str(), (long long)n, field(r, "triangles"), field(r, "objects"), field(r, "elements"),
                        field(r, "links"), field(r, "cluster_links"), field(r, "rays"), field(r, "seconds"),
                        field(r, "cpu_seconds"),
                        field(r, "vmhwm_kb") / 1024.0, field(r, "vmhwm_scene_kb") / 1024.0);
            std::fflush(stdout);
        }
    }
    std::printf("\nLog-log least-squares exponents (y ~ n^b, n = input triangles):\n\n");
    std::printf("| family | sizes | wall time | CPU time | peak memory | memory above the empty process | elements | links | rays |\n|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& fam : families) {
        std::vector<double> n, t, cpu, m, mx, e, l, ry;
        double base = 1e300;
        for (const auto& r : lines)
            if (r.find("\"family\":\"" + fam + "\"") != std::string::npos)
                base = std::min(base, field(r, "vmhwm_scene_kb"));
        for (const auto& r : lines) {
            if (r.find("\"family\":\"" + fam + "\"") == std::string::npos) continue;
            n.push_back(field(r, "triangles"));
            t.push_back(field(r, "seconds"));
            cpu.push_back(field(r, "cpu_seconds"));
            m.push_back(field(r, "vmhwm_kb"));
            mx.push_back(std::max(1.0, field(r, "vmhwm_kb") - base));
            e.push_back(field(r, "elements"));
            l.push_back(field(r, "links"));
            ry.push_back(field(r, "rays"));
        }
        std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", fam.c_str(), n.size(),
                    slope(n, t), slope(n, cpu), slope(n, m), slope(n, mx), slope(n, e), slope(n, l), slope(n, ry));
    }
    for (const auto& [fam, why] : stopped) std::printf("\n%s stopped at %s\n", fam.c_str(), why.c_str());
    return 0;
}
