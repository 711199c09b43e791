//! Camera rays: a thin-lens perspective camera placed by look-from/at/up,
//! with each ray's time uniform in the shutter interval.

use glam::{Vec2, Vec3};

use crate::geometry::Ray;
use crate::sampling::warp::uniform_disk;
use crate::sampling::{Dim, Sampler};
use crate::scene::Camera;
use crate::simd::LANES;

/// Eight rays by coordinate, as [`CameraRays::rays_from8`] makes them: a
/// ray read from here takes each number from one vector store (`[Ray; 8]`,
/// 28 bytes a ray, was read back across two stores and waited on them).
#[derive(Clone, Copy, Debug)]
pub struct RayLanes {
    origin: [[f32; LANES]; 3],
    dir: [[f32; LANES]; 3],
    time: [f32; LANES],
}

impl RayLanes {
    /// The ray of lane `i`.
    #[inline(always)]
    pub fn ray(&self, i: usize) -> Ray {
        let at = |v: &[[f32; LANES]; 3]| Vec3::new(v[0][i], v[1][i], v[2][i]);
        Ray::new(at(&self.origin), at(&self.dir), self.time[i])
    }
}

/// The camera with its frame precomputed for an image size.
#[derive(Clone, Debug)]
pub struct CameraRays {
    origin: Vec3,
    /// The lower left corner of the focus plane's window, relative to
    /// `origin`: ray directions are built from camera-relative vectors, so
    /// they keep their precision however far the camera is from the origin.
    lower_left: Vec3,
    horizontal: Vec3,
    vertical: Vec3,
    u: Vec3,
    v: Vec3,
    lens_radius: f32,
    shutter: (f32, f32),
    size: (f32, f32),
}

impl CameraRays {
    /// The rays of `cam` for a `width` × `height` image, in the frame whose
    /// origin is the scene point `frame` (a world's [`origin`]).
    ///
    /// [`origin`]: crate::geometry::World::origin
    pub fn new(cam: &Camera, width: u32, height: u32, frame: Vec3) -> CameraRays {
        let aspect = width as f32 / height.max(1) as f32;
        let h = (cam.vfov.to_radians() / 2.0).tan();
        let viewport_h = 2.0 * h;
        let viewport_w = aspect * viewport_h;
        let w = (cam.from - cam.at).normalize_or(Vec3::Z);
        let u = cam.up.cross(w).normalize_or(Vec3::X);
        let v = w.cross(u);
        let focus = cam
            .focus_distance
            .unwrap_or_else(|| (cam.at - cam.from).length());
        let horizontal = focus * viewport_w * u;
        let vertical = focus * viewport_h * v;
        CameraRays {
            origin: cam.from - frame,
            lower_left: -horizontal / 2.0 - vertical / 2.0 - focus * w,
            horizontal,
            vertical,
            u,
            v,
            lens_radius: cam.aperture / 2.0,
            shutter: cam.shutter,
            size: (width as f32, height as f32),
        }
    }

    /// A ray through pixel `(x, y)` (row 0 at the top), jittered within it.
    /// Always inlined: with two callers (a sample alone and a block of
    /// samples) the compiler kept it out of line, and the book-2 scene took
    /// 0.2 % more instructions (callgrind, 64² at 16 spp on one thread).
    #[inline(always)]
    pub fn ray(&self, x: u32, y: u32, sampler: &mut Sampler) -> Ray {
        let (film, lens, time) = self.draws(sampler);
        self.ray_from(x, y, film, lens, time)
    }

    /// The camera's draws of the sampler's current sample: its point in
    /// the pixel, on the lens and its time (those a ray reads).
    #[inline(always)]
    pub fn draws(&self, sampler: &mut Sampler) -> (Vec2, Vec2, f32) {
        sampler.begin(Dim::Camera);
        let film = sampler.next_2d();
        // A pinhole needs no lens draw and a closed shutter no time draw;
        // skipping them keeps every other draw as it was.
        let lens = if self.has_lens() {
            sampler.next_2d()
        } else {
            sampler.skip_2d();
            Vec2::ZERO
        };
        let time = if self.has_shutter() {
            sampler.next_1d()
        } else {
            sampler.skip_1d();
            0.0
        };
        (film, lens, time)
    }

    /// [`CameraRays::ray_from`] in each of eight lanes through pixel
    /// `pixel`, for the lanes' film and lens points (`u[0]`, `u[1]`, by
    /// coordinate) and times, compiled with AVX2 where the CPU has it: the
    /// lanes' square roots and divisions run side by side, the same bits
    /// as one ray at a time.
    #[inline]
    pub fn rays_from8(
        &self,
        pixel: (u32, u32),
        u: &[[[f32; LANES]; 2]; 2],
        time: &[f32; LANES],
    ) -> RayLanes {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.rays_from8_avx2(pixel, u, time) };
        }
        self.rays_from8_lanes(pixel, u, time)
    }

    /// [`CameraRays::rays_from8`] compiled with AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn rays_from8_avx2(
        &self,
        pixel: (u32, u32),
        u: &[[[f32; LANES]; 2]; 2],
        time: &[f32; LANES],
    ) -> RayLanes {
        self.rays_from8_lanes(pixel, u, time)
    }

    /// [`CameraRays::ray_from`] lane by lane.
    #[inline(always)]
    fn rays_from8_lanes(
        &self,
        (x, y): (u32, u32),
        [film, lens]: &[[[f32; LANES]; 2]; 2],
        time: &[f32; LANES],
    ) -> RayLanes {
        let mut lanes = RayLanes {
            origin: [[0.0; LANES]; 3],
            dir: [[0.0; LANES]; 3],
            time: [0.0; LANES],
        };
        for i in 0..LANES {
            let at = |u: &[[f32; LANES]; 2]| Vec2::new(u[0][i], u[1][i]);
            let ray = self.ray_from(x, y, at(film), at(lens), time[i]);
            for a in 0..3 {
                lanes.origin[a][i] = ray.origin[a];
                lanes.dir[a][i] = ray.dir[a];
            }
            lanes.time[i] = ray.time;
        }
        lanes
    }

    /// Whether rays start on a lens (a lens draw places them).
    pub fn has_lens(&self) -> bool {
        self.lens_radius > 0.0
    }

    /// Whether rays carry a time drawn in an open shutter.
    pub fn has_shutter(&self) -> bool {
        self.shutter.1 != self.shutter.0
    }

    /// The ray through pixel `(x, y)` for the camera's draws: `film` places
    /// it in the pixel, `lens` on the lens and `time` in the shutter
    /// interval (each read only where the camera has a lens and an open
    /// shutter).
    #[inline(always)]
    pub fn ray_from(&self, x: u32, y: u32, film: Vec2, lens: Vec2, time: f32) -> Ray {
        let s = (x as f32 + film.x) / self.size.0;
        let t = 1.0 - (y as f32 + film.y) / self.size.1;
        let offset = if self.has_lens() {
            let lens = uniform_disk(lens);
            self.lens_radius * (lens.x * self.u + lens.y * self.v)
        } else {
            Vec3::ZERO
        };
        let origin = self.origin + offset;
        let to_target = self.lower_left + s * self.horizontal + t * self.vertical - offset;
        let time = if self.has_shutter() {
            self.shutter.0 + (self.shutter.1 - self.shutter.0) * time
        } else {
            self.shutter.0
        };
        Ray::new(origin, to_target.normalize(), time)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SamplerKind;

    #[test]
    fn centre_ray_looks_at_target_and_time_stays_in_shutter() {
        let cam = Camera {
            from: Vec3::new(278.0, 278.0, -800.0),
            at: Vec3::new(278.0, 278.0, 0.0),
            shutter: (0.25, 0.5),
            ..Camera::default()
        };
        let rays = CameraRays::new(&cam, 101, 101, Vec3::ZERO);
        for i in 0..100 {
            let mut sampler = Sampler::for_sample(SamplerKind::Sobol, 0, 50, 50, i);
            let r = rays.ray(50, 50, &mut sampler);
            assert!(r.dir.dot(Vec3::Z) > 0.9999);
            assert!((0.25..=0.5).contains(&r.time));
        }
        // Pixel column 0 is on the image's left: +x for a camera looking +z.
        let mut sampler = Sampler::for_sample(SamplerKind::Independent, 0, 0, 50, 0);
        let left = rays.ray(0, 50, &mut sampler);
        assert!(left.dir.x > 0.0);
    }
}
