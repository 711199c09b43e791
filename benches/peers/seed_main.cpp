// seed_main.cpp — benchmark driver for the seed renderer (the C++ path tracer
// of github.com/everaindcy/ComputerGraphics that rtlang re-creates), used by
// seed_cpp.py. It is compiled together with the seed's sources, which stay
// outside this repository (seed_cpp.py takes their path on its command line):
//
//   g++ -O2 -fopenmp -std=c++17 -I SEED/src seed_main.cpp -o seed_bench
//   OMP_NUM_THREADS=2 ./seed_bench SCENE WIDTH HEIGHT SPP DEPTH [-o OUT.ppm] [--procs N]
//
// It builds one of the seed's scenes with the seed's own scene code
// (scene_gen, curve_scene2, motion_bunny_scene), overrides image size,
// samples per pixel and maximum depth, and renders with the seed's
// integrator (`ray_color` of the seed's main.cc, included below with its
// `main` renamed away). By default it runs an OpenMP loop over rows shaped
// like the seed's main.cc (dynamic schedule, 10 rows a chunk). With
// `--procs N` it instead forks N single-threaded processes, as the seed's
// main_multi_process.cc does on Linux (its report: OpenMP "performs poorly
// on Linux"; its random numbers come from one global generator that OpenMP
// threads share), each taking every N-th row, their sums in shared memory.
// Run it in a directory holding the seed's `textures/` (and `meshs/` for
// the mesh scene): the seed loads those by relative path.
//
// Prints on stdout:
//   render_seconds S     wall time of the render alone (no scene build; with
//                        --procs, from the first fork to the last exit)
//   rays N               rays traced (calls of the world's hit() by ray_color)
//   mean_linear R G B    the image's mean radiance, linear, before the seed's
//                        gamma 2 and clamp
// and, given -o OUT.ppm, writes the image the way the seed does (P3, gamma 2).

// Headers the seed's code uses without including them (it built with an
// older g++ whose headers pulled them in).
#include <chrono>
#include <functional>

#define main seed_original_main // keep the seed's own main out of the way
#include "main.cc"
#undef main
#include "scene/scenes.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

// The seed scene rtlang's scenes/NAME.rt describes.
bool build_scene(const std::string& name, scene& sce) {
    if (name == "spheres") scene_gen(sce, 1);            // book 1 random spheres
    else if (name == "cornell") scene_gen(sce, 6);       // Cornell box
    else if (name == "cornell_smoke") scene_gen(sce, 7); // Cornell box, smoke
    else if (name == "next_week") scene_gen(sce, 8);     // book 2 final scene
    else if (name == "revolution") scene_gen(sce, 20);   // mirror surface of revolution
    else if (name == "vase") sce = curve_scene2();       // the textured vase
    else if (name == "mesh") sce = motion_bunny_scene(); // bunny and mirror vase
    else return false;
    return true;
}

// The scene as ray_color sees it, counting the rays it traces: every call of
// ray_color with depth left traces one ray through the world's hit().
thread_local unsigned long long rays_traced = 0;

struct counted_world : hittable {
    explicit counted_world(const hittable& world) : world(world) {}
    bool hit(const ray& r, double t_min, double t_max, hit_record& rec) const override {
        ++rays_traced;
        return world.hit(r, t_min, t_max, rec);
    }
    bool bounding_box(double time0, double time1, aabb& box) const override {
        return world.bounding_box(time0, time1, box);
    }
    const hittable& world;
};

// One row (top down) of samples with the seed's camera and ray_color, its
// per-pixel sums of radiance into sums[3 * (row * width + i) ..]; returns
// the rays it traced.
unsigned long long render_row(const scene& sce, const hittable& world, int row, double* sums) {
    const unsigned long long rays_before = rays_traced;
    const int width = sce.image_width, height = sce.image_height;
    const int j = height - 1 - row; // v runs bottom up
    for (int i = 0; i < width; ++i) {
        color sum(0, 0, 0);
        for (int s = 0; s < sce.samples_per_pixel; ++s) {
            const double u = (i + random_double()) / width;
            const double v = (j + random_double()) / height;
            sum += ray_color(sce.cam->get_ray(u, v), sce.background, world, sce.max_depth);
        }
        double* px = sums + 3 * (size_t(row) * width + i);
        px[0] = sum.x();
        px[1] = sum.y();
        px[2] = sum.z();
    }
    return rays_traced - rays_before;
}

int usage(const char* argv0) {
    std::fprintf(stderr,
                 "usage: %s SCENE WIDTH HEIGHT SPP DEPTH [-o OUT.ppm] [--procs N]\n"
                 "scenes: spheres cornell cornell_smoke next_week revolution vase mesh\n",
                 argv0);
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 6) return usage(argv[0]);
    const std::string name = argv[1];
    const int width = std::atoi(argv[2]);
    const int height = std::atoi(argv[3]);
    const int spp = std::atoi(argv[4]);
    const int depth = std::atoi(argv[5]);
    const char* out_path = nullptr;
    int procs = 0; // 0: OpenMP threads
    for (int a = 6; a < argc; ++a) {
        if (!std::strcmp(argv[a], "-o") && a + 1 < argc) out_path = argv[++a];
        else if (!std::strcmp(argv[a], "--procs") && a + 1 < argc) procs = std::atoi(argv[++a]);
        else return usage(argv[0]);
    }
    if (width <= 0 || height <= 0 || spp <= 0 || depth <= 0 || procs < 0) {
        std::fprintf(stderr, "width, height, spp and depth must be positive\n");
        return 2;
    }

    scene sce;
    if (!build_scene(name, sce)) {
        std::fprintf(stderr, "unknown scene `%s`\n", name.c_str());
        return 2;
    }
    // Our size, with square pixels: the camera's aspect follows the image.
    sce.image_width = width;
    sce.image_height = height;
    sce.aspect_ratio = double(width) / double(height);
    sce.samples_per_pixel = spp;
    sce.max_depth = depth;
    sce.resetcam();

    // Shared with the forked processes when there are any: the pixels' sums,
    // then each row's ray count.
    const size_t bytes = sizeof(double) * 3 * size_t(width) * height
                         + sizeof(unsigned long long) * height;
    void* shared = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (shared == MAP_FAILED) {
        std::perror("mmap");
        return 1;
    }
    double* sums = static_cast<double*>(shared);
    auto* row_rays = reinterpret_cast<unsigned long long*>(sums + 3 * size_t(width) * height);
    const counted_world world(sce.objs);

    const auto t0 = std::chrono::steady_clock::now();
    if (procs == 0) {
#pragma omp parallel for schedule(dynamic, 10)
        for (int row = 0; row < height; ++row) row_rays[row] = render_row(sce, world, row, sums);
    } else {
        for (int k = 0; k < procs; ++k) {
            const pid_t pid = fork();
            if (pid < 0) {
                std::perror("fork");
                return 1;
            }
            if (pid == 0) { // a child: every procs-th row from row k
                for (int row = k; row < height; row += procs)
                    row_rays[row] = render_row(sce, world, row, sums);
                _exit(0);
            }
        }
        int status = 0, failed = 0;
        while (wait(&status) > 0) failed |= !WIFEXITED(status) || WEXITSTATUS(status) != 0;
        if (failed) {
            std::fprintf(stderr, "a render process failed\n");
            return 1;
        }
    }
    const auto t1 = std::chrono::steady_clock::now();

    image img(width, height);
    double mean[3] = {0, 0, 0};
    for (int row = 0; row < height; ++row) {
        for (int i = 0; i < width; ++i) {
            const double* px = sums + 3 * (size_t(row) * width + i);
            for (int c = 0; c < 3; ++c) mean[c] += px[c] / spp;
            write_color(img, color(px[0], px[1], px[2]), spp, row, i); // the seed's gamma 2
        }
    }
    unsigned long long rays = 0;
    for (int row = 0; row < height; ++row) rays += row_rays[row];
    const double pixels = double(width) * double(height);
    std::printf("render_seconds %.6f\n", std::chrono::duration<double>(t1 - t0).count());
    std::printf("rays %llu\n", rays);
    std::printf("mean_linear %.6f %.6f %.6f\n", mean[0] / pixels, mean[1] / pixels,
                mean[2] / pixels);
    std::fflush(stdout);

    if (out_path) {
        std::ofstream out(out_path);
        std::streambuf* saved = std::cout.rdbuf(out.rdbuf());
        img.print_ppm(); // the seed's own writer, which prints to std::cout
        std::cout.flush();
        std::cout.rdbuf(saved);
    }
    munmap(shared, bytes);
    return 0;
}
