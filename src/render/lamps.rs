//! Lights that are not shapes, in the world's frame, ready to sample and
//! look up: point and spot lights (delta positions: found by light sampling
//! only), the sun (a delta direction, or a cone of directions of uniform
//! radiance when it has an angular diameter) and the environment image.
//! Their choice among the other lights is [`super::lights::LightList`]'s.
//!
//! Units: a point or spot light gives `intensity` (W/sr), so the radiance
//! it sends a point at distance d is I / d² along one direction. The sun is
//! given by the irradiance E of a surface facing it; a sun of angular
//! radius α > 0 is a disk of radiance L = E / (π sin² α), whose integral of
//! L cos θ over the disk is E. A spot falls off as Mitsuba's `spot`: full
//! up to `beam` from its axis, linearly in angle to zero at `cutoff`.

use crate::geometry::emitter::LightId;
use std::f32::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

use super::environment::EnvironmentMap;
use super::light_tree::LightBounds;
use super::lights::{luminance, LightSample};
use crate::geometry::ray::SurfacePoint;
use crate::sampling::warp::sin_cos_turn;
use crate::scene::light::placed_lamps;
use crate::scene::{Background, Lamp, Scene};

/// One light that is not a shape.
#[derive(Clone, Debug)]
pub(super) enum LampLight {
    Point {
        at: Vec3,
        intensity: Vec3,
    },
    Spot {
        at: Vec3,
        axis: Vec3,
        intensity: Vec3,
        cos_cutoff: f32,
        cos_beam: f32,
        cutoff: f32,
        /// 1 / (cutoff − beam), in 1/radians (infinite for a hard edge).
        inv_transition: f32,
    },
    Sun {
        /// Unit direction towards the sun.
        toward: Vec3,
        /// cos of the angular radius (1: a delta direction).
        cos_max: f32,
        /// Irradiance for a delta sun, radiance for a disk.
        value: Vec3,
    },
    Environment(Box<EnvironmentMap>),
}

/// The lamps and environment of `scene` in the frame whose origin is the
/// scene point `origin`, each emitting something: lamps placed by the
/// object tree first in its order, then the environment. Without light
/// sampling only the lights a path can find by scattering are kept.
pub(super) fn prepare(scene: &Scene, origin: Vec3, light_sampling: bool) -> Vec<LampLight> {
    let mut out: Vec<LampLight> = placed_lamps(scene)
        .iter()
        .filter_map(|l| LampLight::new(l, origin))
        .collect();
    if let Background::Environment(env) = &scene.settings.background {
        let map = EnvironmentMap::new(env);
        if map.luminous_integral() > 0.0 {
            out.push(LampLight::Environment(Box::new(map)));
        }
    }
    if !light_sampling {
        out.retain(|l| !l.is_delta());
    }
    // Point and spot lights first: they are the light tree's leaves.
    out.sort_by_key(LampLight::is_distant);
    out
}

impl LampLight {
    /// The lamp `l` in the frame at `origin`; `None` if it emits nothing.
    fn new(l: &Lamp, origin: Vec3) -> Option<LampLight> {
        let bright = |c: Vec3| luminance(c) > 0.0;
        Some(match *l {
            Lamp::Point { at, intensity } => {
                bright(intensity).then_some(())?;
                LampLight::Point {
                    at: at - origin,
                    intensity,
                }
            }
            Lamp::Spot {
                at,
                to,
                intensity,
                cutoff,
                beam,
            } => {
                bright(intensity).then_some(())?;
                let axis = (to - at).try_normalize()?;
                let beam = beam.min(cutoff);
                LampLight::Spot {
                    at: at - origin,
                    axis,
                    intensity,
                    cos_cutoff: cutoff.cos(),
                    cos_beam: beam.cos(),
                    cutoff,
                    inv_transition: 1.0 / (cutoff - beam),
                }
            }
            Lamp::Sun {
                direction,
                irradiance,
                diameter,
            } => {
                bright(irradiance).then_some(())?;
                let toward = direction.try_normalize()?;
                let half = 0.5 * diameter;
                let value = if half > 0.0 {
                    irradiance / (PI * half.sin().powi(2))
                } else {
                    irradiance
                };
                LampLight::Sun {
                    toward,
                    cos_max: half.cos(),
                    value,
                }
            }
        })
    }

    /// Whether only light sampling finds this light.
    pub fn is_delta(&self) -> bool {
        match self {
            LampLight::Point { .. } | LampLight::Spot { .. } => true,
            LampLight::Sun { cos_max, .. } => *cos_max >= 1.0,
            LampLight::Environment(_) => false,
        }
    }

    /// Whether the light is at infinity (outside the light tree).
    pub fn is_distant(&self) -> bool {
        matches!(self, LampLight::Sun { .. } | LampLight::Environment(_))
    }

    /// The power used to choose among lights, in the unit of the area
    /// lights' (luminance × area, power / π); distant lights as seen by a
    /// disk of the world's bounding `radius`.
    pub fn power(&self, radius: f64) -> f64 {
        let r2 = radius * radius;
        match self {
            LampLight::Point { intensity, .. } => 4.0 * f64::from(luminance(*intensity)),
            LampLight::Spot {
                intensity,
                cos_cutoff,
                cos_beam,
                ..
            } => {
                let cone = 1.0 - 0.5 * f64::from(cos_cutoff + cos_beam);
                2.0 * cone * f64::from(luminance(*intensity))
            }
            LampLight::Sun { value, cos_max, .. } => {
                let e = if *cos_max >= 1.0 {
                    f64::from(luminance(*value))
                } else {
                    f64::from(luminance(*value))
                        * std::f64::consts::PI
                        * (1.0 - f64::from(cos_max * cos_max))
                };
                e * r2
            }
            LampLight::Environment(map) => map.luminous_integral() * r2,
        }
    }

    /// The light tree's bounds of a point or spot light of `power`.
    pub fn bounds(&self, power: f64) -> Option<LightBounds> {
        let (at, axis, cos_spread) = match self {
            LampLight::Point { at, .. } => (*at, DVec3::Z, -1.0),
            // The tree bounds emission within 90° of a normal cone: a cone
            // of `cutoff − 90°` holds the spot's beam.
            LampLight::Spot {
                at, axis, cutoff, ..
            } => (
                *at,
                axis.as_dvec3(),
                f64::from((cutoff - 0.5 * PI).max(0.0)).cos(),
            ),
            _ => return None,
        };
        Some(LightBounds {
            min: at.as_dvec3(),
            max: at.as_dvec3(),
            power,
            axis,
            cos_spread,
            two_sided: false,
        })
    }

    /// The spot's falloff towards the unit direction `d` from the light.
    fn falloff(axis: Vec3, cos_cutoff: f32, cos_beam: f32, cutoff: f32, inv: f32, d: Vec3) -> f32 {
        let c = axis.dot(d);
        if c <= cos_cutoff {
            0.0
        } else if c >= cos_beam {
            1.0
        } else {
            ((cutoff - c.clamp(-1.0, 1.0).acos()) * inv).clamp(0.0, 1.0)
        }
    }

    /// A light sample seen from `p` with the draws `u`, its density not yet
    /// multiplied by the choice's probability (1 for a delta light); a
    /// distant light's shadow ray ends `far` away. `None` if nothing
    /// arrives.
    pub fn sample(&self, p: Vec3, u: Vec2, far: f32) -> Option<LightSample> {
        let at_point = |at: Vec3, intensity: Vec3| {
            let to = at - p;
            let d2 = to.length_squared();
            let dist = d2.sqrt();
            (dist > 0.0).then(|| LightSample {
                dir: to / dist,
                dist,
                emitted: intensity / d2,
                pdf: 1.0,
                target: SurfacePoint {
                    point: at,
                    error: Vec3::ZERO,
                    normal: Vec3::ZERO,
                },
                delta: true,
                emitter: LightId::NONE,
            })
        };
        let distant = |dir: Vec3, emitted: Vec3, pdf: f32, delta: bool| LightSample {
            dir,
            dist: far,
            emitted,
            pdf,
            target: SurfacePoint {
                point: p + dir * far,
                error: Vec3::ZERO,
                normal: Vec3::ZERO,
            },
            delta,
            emitter: LightId::NONE,
        };
        match self {
            LampLight::Point { at, intensity } => at_point(*at, *intensity),
            &LampLight::Spot {
                at,
                axis,
                intensity,
                cos_cutoff,
                cos_beam,
                cutoff,
                inv_transition,
            } => {
                let mut s = at_point(at, intensity)?;
                let f = Self::falloff(axis, cos_cutoff, cos_beam, cutoff, inv_transition, -s.dir);
                (f > 0.0).then(|| {
                    s.emitted *= f;
                    s
                })
            }
            &LampLight::Sun {
                toward,
                cos_max,
                value,
            } => {
                if cos_max >= 1.0 {
                    return Some(distant(toward, value, 1.0, true));
                }
                let one_minus_cos = u.x * (1.0 - cos_max);
                let cos = 1.0 - one_minus_cos;
                let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
                let (t, b) = toward.any_orthonormal_pair();
                let (s, c) = sin_cos_turn(u.y);
                let dir = (sin * c * t + sin * s * b + cos * toward).normalize();
                Some(distant(dir, value, self.pdf(dir), false))
            }
            LampLight::Environment(map) => {
                let (dir, l, pdf) = map.sample(u)?;
                Some(distant(dir, l, pdf, false))
            }
        }
    }

    /// The solid-angle density of [`LampLight::sample`] choosing the unit
    /// direction `dir` (0 for delta lights and outside a sun's disk).
    pub fn pdf(&self, dir: Vec3) -> f32 {
        match self {
            &LampLight::Sun {
                toward, cos_max, ..
            } if cos_max < 1.0 && toward.dot(dir) >= cos_max => 1.0 / (TAU * (1.0 - cos_max)),
            LampLight::Environment(map) => map.pdf(dir),
            _ => 0.0,
        }
    }

    /// The radiance a ray leaving the scene along the unit direction `dir`
    /// finds (0 for delta lights).
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match self {
            &LampLight::Sun {
                toward,
                cos_max,
                value,
            } if cos_max < 1.0 && toward.dot(dir) >= cos_max => value,
            LampLight::Environment(map) => map.radiance(dir),
            _ => Vec3::ZERO,
        }
    }
}
