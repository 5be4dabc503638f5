//! The car as a rapier2d rigid body among road edges, barriers and cones.
//!
//! # How the tyre forces drive the body
//!
//! Rapier integrates positions with the body's velocity over the step (`x += dt·v`,
//! `θ += dt·ω`). [`World::step`] wraps that drift in two half "kicks" (Störmer–Verlet,
//! kick–drift–kick): before the rapier step it applies to the body the impulse of the tyre and
//! pedal forces of eq. C.1–C.3 over the first half step, and after it the impulse over the
//! second half. Each impulse is the RK4 integral of the body-frame forces over its half step,
//! so the velocities follow the Appendix C dynamics to fourth order and the pose follows them
//! to second order (the midpoint rule of the drift). Contacts with barriers change the
//! velocity inside the rapier step and are carried into the next kick. The cross-check test
//! holds this motion to 2 cm and 0.2° of an independent adaptive integration over 20 s.
//!
//! The world is rapier2d's `f64` build (`rapier2d-f64`): with `f32` positions the rounding of
//! `x += dt·v` is systematic when the velocity is steady, and measured about 2.5 cm of drift
//! after 300 m in the sine-steer cross-check. rapier speaks glam; this module converts at its
//! boundary and its API uses only `f64` and `[f64; 2]`.
//!
//! # Without rapier's pipeline on a track with no barrier
//!
//! rapier2d's pipeline allocates on every step, and the haptic thread must not. On a track
//! with no solid barrier (every exercise's) the car meets no solid contact, so [`World::step`]
//! moves it as rapier's solver moves a free body and asks parry which sensors it touches, in
//! the same arithmetic and without allocating (`world::free`); rapier holds the track's colliders
//! and is the oracle the tests hold that path to, bit for bit. A track with barriers steps
//! rapier's whole pipeline, whose contacts change the car's velocity.
//!
//! # Events
//!
//! Road edges are sensor polylines, cones are small sensor discs, barriers are solid
//! polylines. After each step the world compares what the car's body touches with the
//! previous step and reports [`WorldEvent`]s: a cone hit (once per cone), a road edge touched
//! and later cleared (saying whether the car then lies outside the road) and barrier contacts.

mod free;

use rapier2d_f64::math::Vector as Vec2;
use rapier2d_f64::prelude::{
    ColliderBuilder, ColliderHandle, MassProperties, PhysicsWorld, RigidBodyBuilder,
    RigidBodyHandle,
};

use common::wrap_angle;
use free::{FreeCar, Sensors};

use crate::error::VehicleError;
use crate::model::{DriverInput, TyreForces, VehicleParams, VehicleState, body_forces, rk4};
use crate::road::Road;

/// Segments per edge or barrier collider: short polylines let the broad phase skip the parts
/// of a long road far from the car.
const SEGMENTS_PER_COLLIDER: usize = 16;

/// Contacts (and events) one step is expected to produce at most; the buffers are sized for
/// it up front so a step with contacts does not allocate in our code (rapier's own narrow
/// phase may still grow its buffers the first time a pair touches).
const MAX_EVENTS_PER_STEP: usize = 64;

/// Which side of the road, looking along increasing arc length.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Side {
    /// Left edge (positive lateral offset).
    Left,
    /// Right edge.
    Right,
}

/// What the car touched during a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorldEvent {
    /// The car's body first overlapped cone number `cone` (index into [`TrackLayout::cones`]).
    ConeHit {
        /// Index of the cone.
        cone: usize,
    },
    /// The car's body started to overlap a road edge line.
    EdgeTouched {
        /// Which edge.
        side: Side,
    },
    /// The car's body stopped overlapping a road edge line.
    EdgeCleared {
        /// Which edge.
        side: Side,
        /// `true` when the car's centre is now outside that edge (it left the road), `false`
        /// when it came back onto the road.
        off_road: bool,
    },
    /// The car's body started touching a barrier (a solid contact).
    BarrierHit,
}

/// Static geometry of a track, in world coordinates (m).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackLayout {
    /// Left road edge, a polyline in the direction of travel.
    pub left_edge: Vec<[f64; 2]>,
    /// Right road edge, a polyline in the direction of travel.
    pub right_edge: Vec<[f64; 2]>,
    /// Solid barriers, each a polyline.
    pub barriers: Vec<Vec<[f64; 2]>>,
    /// Cone positions.
    pub cones: Vec<[f64; 2]>,
    /// Cone radius at the base, m.
    pub cone_radius_m: f64,
}

impl TrackLayout {
    /// Edges at ±`half_width_m` of `road`'s centre line from 0 to `length_m`, sampled every
    /// `spacing_m`; with `barrier_offset_m`, solid barriers that far outside each edge.
    pub fn along_road(
        road: &dyn Road,
        length_m: f64,
        half_width_m: f64,
        spacing_m: f64,
        barrier_offset_m: Option<f64>,
    ) -> Self {
        let n = ((length_m / spacing_m).ceil() as usize).max(1);
        let offset_line = |off: f64| -> Vec<[f64; 2]> {
            (0..=n)
                .map(|i| {
                    let s = (i as f64 * spacing_m).min(length_m);
                    let ([x, y], h, _) = road.centre(s);
                    [x - off * h.sin(), y + off * h.cos()]
                })
                .collect()
        };
        let barriers = match barrier_offset_m {
            Some(b) => vec![
                offset_line(half_width_m + b),
                offset_line(-(half_width_m + b)),
            ],
            None => Vec::new(),
        };
        Self {
            left_edge: offset_line(half_width_m),
            right_edge: offset_line(-half_width_m),
            barriers,
            cones: Vec::new(),
            cone_radius_m: 0.2,
        }
    }
}

/// What a collider of the track is. Ordered: the tags touching in a step are sorted, so
/// events of one step come in the same order whichever path found them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Tag {
    Edge(Side),
    Barrier,
    Cone(usize),
}

/// How a step moves the car (module docs).
enum Motion {
    /// No solid barrier: the car is a free body moved by `free`, allocation-free.
    Free {
        /// The car's body as rapier's solver would have it.
        car: FreeCar,
        /// The edges and cones.
        sensors: Sensors,
    },
    /// Barriers: rapier's pipeline moves the car's rapier body.
    Solver,
}

/// A rapier2d world holding the car and the track. See the module docs.
pub struct World {
    physics: PhysicsWorld,
    motion: Motion,
    car: RigidBodyHandle,
    car_collider: ColliderHandle,
    tags: Vec<(ColliderHandle, Tag)>,
    layout: TrackLayout,
    params: VehicleParams,
    /// Unwrapped heading, rad (rapier's rotation only knows (−π, π]).
    yaw_rad: f64,
    tyres: TyreForces,
    touching: Vec<Tag>,
    /// Scratch list of the tags touching now, reused every step.
    touching_now: Vec<Tag>,
    cones_hit: Vec<bool>,
    events: Vec<WorldEvent>,
}

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

impl World {
    /// A world with the car (`params`, starting at `start`) on `layout`.
    pub fn new(
        params: VehicleParams,
        start: VehicleState,
        layout: TrackLayout,
    ) -> Result<Self, VehicleError> {
        params.validate()?;
        if !start.is_finite() {
            return Err(VehicleError::InvalidInput(format!(
                "start state must be finite: {start:?}"
            )));
        }
        let mut physics = PhysicsWorld::new();
        physics.gravity = Vec2::ZERO;
        // One solver iteration (rapier's default is 4 sub-steps): a lone car against static
        // barriers needs no more, and the free motion is exact either way.
        physics.integration_parameters.num_solver_iterations = 1;
        let (sy, cy) = start.yaw_rad.sin_cos();
        let v_world = [
            cy * start.ux_m_s - sy * start.uy_m_s,
            sy * start.ux_m_s + cy * start.uy_m_s,
        ];
        let body = RigidBodyBuilder::dynamic()
            .translation(v2([start.x_m, start.y_m]))
            .rotation(start.yaw_rad)
            .linvel(v2(v_world))
            .angvel(start.r_rad_s)
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vec2::ZERO,
                params.mass_kg,
                params.yaw_inertia_kg_m2,
            ));
        // The body box is centred between the axles' overhangs; the CG is the body origin.
        let offset = (params.cg_to_front_m - params.cg_to_rear_m) / 2.0;
        let car_shape =
            ColliderBuilder::cuboid(params.body_length_m / 2.0, params.body_width_m / 2.0)
                .translation(Vec2::new(offset, 0.0))
                .density(0.0)
                .friction(0.3);
        let (car, car_collider) = physics.insert(body, car_shape);
        // rapier computes the mass properties lazily at the first step; without this the very
        // first kick (an impulse) would meet a zero inverse mass and be lost.
        let colliders = &physics.colliders;
        physics.bodies[car].recompute_mass_properties_from_colliders(colliders);

        let mut tags = Vec::new();
        let mut add_polyline = |physics: &mut PhysicsWorld, line: &[[f64; 2]], tag: Tag| {
            for chunk in line
                .windows(2)
                .collect::<Vec<_>>()
                .chunks(SEGMENTS_PER_COLLIDER)
            {
                let mut pts: Vec<Vec2> = chunk.iter().map(|w| v2(w[0])).collect();
                pts.push(v2(chunk[chunk.len() - 1][1]));
                let sensor = !matches!(tag, Tag::Barrier);
                let (_, h) = physics.insert(
                    RigidBodyBuilder::fixed(),
                    ColliderBuilder::polyline(pts, None).sensor(sensor),
                );
                tags.push((h, tag));
            }
        };
        add_polyline(&mut physics, &layout.left_edge, Tag::Edge(Side::Left));
        add_polyline(&mut physics, &layout.right_edge, Tag::Edge(Side::Right));
        for b in &layout.barriers {
            add_polyline(&mut physics, b, Tag::Barrier);
        }
        for (i, c) in layout.cones.iter().enumerate() {
            let (_, h) = physics.insert(
                RigidBodyBuilder::fixed().translation(v2(*c)),
                ColliderBuilder::ball(layout.cone_radius_m.max(0.01)).sensor(true),
            );
            tags.push((h, Tag::Cone(i)));
        }
        tags.sort_by_key(|(h, _)| h.into_raw_parts());
        let cones_hit = vec![false; layout.cones.len()];
        let motion = if layout.barriers.is_empty() {
            Self::free_motion(&physics, car, car_collider, &tags)
        } else {
            Motion::Solver
        };
        Ok(Self {
            physics,
            motion,
            car,
            car_collider,
            tags,
            layout,
            params,
            yaw_rad: start.yaw_rad,
            tyres: TyreForces::default(),
            touching: Vec::with_capacity(MAX_EVENTS_PER_STEP),
            touching_now: Vec::with_capacity(MAX_EVENTS_PER_STEP),
            cones_hit,
            // Room for more contacts than one step can produce: pushing never allocates.
            events: Vec::with_capacity(MAX_EVENTS_PER_STEP),
        })
    }

    /// The free path's car and sensors, from rapier's car body and the track's colliders.
    fn free_motion(
        physics: &PhysicsWorld,
        car: RigidBodyHandle,
        car_collider: ColliderHandle,
        tags: &[(ColliderHandle, Tag)],
    ) -> Motion {
        let car_local = physics.colliders[car_collider]
            .position_wrt_parent()
            .copied()
            .unwrap_or_default();
        Motion::Free {
            car: FreeCar::of(&physics.bodies[car]),
            sensors: Sensors::new(&physics.colliders, tags.iter().map(|(h, _)| *h), car_local),
        }
    }

    /// The same world with rapier's whole pipeline moving the car even with no barrier (it
    /// allocates on every step): the oracle the free path is tested against, and the
    /// reference the benchmarks compare it with.
    pub fn with_rapier_pipeline(mut self) -> Self {
        self.motion = Motion::Solver;
        self
    }

    /// The car moves as a free body, not through rapier's pipeline (module docs).
    #[cfg(test)]
    pub(crate) fn moves_free(&self) -> bool {
        matches!(self.motion, Motion::Free { .. })
    }

    /// The car's parameters.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// The track geometry.
    pub fn layout(&self) -> &TrackLayout {
        &self.layout
    }

    /// The car's state as the rapier body has it (pose and body-frame velocities).
    pub fn state(&self) -> VehicleState {
        let (t, v, r) = self.body_motion();
        let (sy, cy) = self.yaw_rad.sin_cos();
        let (vx, vy) = (v.x, v.y);
        VehicleState {
            x_m: t.x,
            y_m: t.y,
            yaw_rad: self.yaw_rad,
            ux_m_s: cy * vx + sy * vy,
            uy_m_s: -sy * vx + cy * vy,
            r_rad_s: r,
        }
    }

    /// The car body's position (m), world velocity (m/s) and yaw rate (rad/s).
    fn body_motion(&self) -> (Vec2, Vec2, f64) {
        match &self.motion {
            Motion::Free { car, .. } => (car.translation, car.linvel, car.angvel),
            Motion::Solver => {
                let body = &self.physics.bodies[self.car];
                (body.translation(), body.linvel(), body.angvel())
            }
        }
    }

    /// The body's rotation angle, rad, in (−π, π].
    fn body_angle(&self) -> f64 {
        match &self.motion {
            Motion::Free { car, .. } => car.rotation.angle(),
            Motion::Solver => self.physics.bodies[self.car].rotation().angle(),
        }
    }

    /// Tyre forces at the end of the last step.
    pub fn tyre_forces(&self) -> TyreForces {
        self.tyres
    }

    /// Cones hit so far.
    pub fn cone_hits(&self) -> usize {
        self.cones_hit.iter().filter(|h| **h).count()
    }

    /// Events since the last call, oldest first. Drains in place: the buffer keeps its
    /// capacity, so the haptic loop never allocates for contacts.
    pub fn drain_events(&mut self) -> std::vec::Drain<'_, WorldEvent> {
        self.events.drain(..)
    }

    /// Set the body's world velocity from body-frame velocities at heading `yaw` by applying
    /// the impulse that takes it there (the time integral of the tyre forces).
    fn kick_to(&mut self, yaw: f64, ux: f64, uy: f64, r: f64) {
        let (sy, cy) = yaw.sin_cos();
        let target = v2([cy * ux - sy * uy, sy * ux + cy * uy]);
        let (_, linvel, angvel) = self.body_motion();
        let impulse = (target - linvel) * self.params.mass_kg;
        let torque_impulse = (r - angvel) * self.params.yaw_inertia_kg_m2;
        match &mut self.motion {
            Motion::Free { car, .. } => car.kick(impulse, torque_impulse),
            Motion::Solver => {
                let body = &mut self.physics.bodies[self.car];
                body.apply_impulse(impulse, true);
                body.apply_torque_impulse(torque_impulse, true);
            }
        }
    }

    /// Drift: move the body over the step, and list in `touching_now` the colliders it touches
    /// (as rapier does, from the pose the step starts from).
    fn drift(&mut self, dt_s: f64) {
        self.physics.integration_parameters.dt = dt_s;
        let mut now = std::mem::take(&mut self.touching_now);
        now.clear();
        let tags = &self.tags;
        match &mut self.motion {
            Motion::Free { car, sensors } => {
                let colliders = &self.physics.colliders;
                let shape = colliders[self.car_collider].shape();
                sensors.touching(colliders, shape, &car.pose(), |h| {
                    now.extend(tag_of(tags, h));
                });
                car.drift(&self.physics.integration_parameters);
            }
            Motion::Solver => {
                self.physics.step();
                let car = self.car_collider;
                let other = |a, b| if a == car { b } else { a };
                let np = &self.physics.narrow_phase;
                now.extend(
                    np.intersection_pairs_with(car)
                        .filter(|(_, _, hit)| *hit)
                        .filter_map(|(a, b, _)| tag_of(tags, other(a, b))),
                );
                now.extend(
                    np.contact_pairs_with(car)
                        .filter(|p| p.has_any_active_contact())
                        .filter_map(|p| tag_of(tags, other(p.collider1, p.collider2))),
                );
            }
        }
        self.touching_now = now;
    }

    /// Advance by `dt_s` seconds with driver input `input` (kick–drift–kick, module docs).
    /// Non-finite input fields count as zero; a non-positive or non-finite `dt_s` does nothing.
    pub fn step(&mut self, input: DriverInput, dt_s: f64) {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let fin = |v: f64| if v.is_finite() { v } else { 0.0 };
        let input = DriverInput {
            steer_rad: fin(input.steer_rad),
            drive_force_n: fin(input.drive_force_n),
            brake_force_n: fin(input.brake_force_n),
        }
        .clamped(&self.params);
        let half = dt_s / 2.0;
        // Kick: tyre-force impulse over the first half step.
        let s0 = self.state();
        let h = rk4(&self.params, &s0, &input, half);
        self.kick_to(h.yaw_rad, h.ux_m_s, h.uy_m_s, h.r_rad_s);
        // Drift: the body moves (rapier resolves contacts with barriers).
        self.drift(dt_s);
        let angle = self.body_angle();
        self.yaw_rad += wrap_angle(angle - self.yaw_rad);
        // Kick: second half, from the mid-step velocities (contact impulses included).
        let (_, v, r) = self.body_motion();
        let (vx, vy) = (v.x, v.y);
        let (sy, cy) = h.yaw_rad.sin_cos();
        let mid = VehicleState {
            ux_m_s: cy * vx + sy * vy,
            uy_m_s: -sy * vx + cy * vy,
            r_rad_s: r,
            ..s0
        };
        let e = rk4(&self.params, &mid, &input, half);
        self.kick_to(self.yaw_rad, e.ux_m_s, e.uy_m_s, e.r_rad_s);
        self.tyres = body_forces(&self.params, &self.state(), &input).1;
        self.collect_events();
    }

    /// Events from the tags the step found touching (`touching_now`) against the last step's.
    fn collect_events(&mut self) {
        let mut now = std::mem::take(&mut self.touching_now);
        // Several chunks of one edge can touch the car at once: keep one tag of each, in
        // their order (an in-place sort: no allocation).
        now.sort_unstable();
        now.dedup();
        let pos = self.state();
        for tag in &now {
            if self.touching.contains(tag) {
                continue;
            }
            match *tag {
                Tag::Cone(i) if !self.cones_hit[i] => {
                    self.cones_hit[i] = true;
                    self.events.push(WorldEvent::ConeHit { cone: i });
                }
                Tag::Edge(side) => self.events.push(WorldEvent::EdgeTouched { side }),
                Tag::Barrier => self.events.push(WorldEvent::BarrierHit),
                Tag::Cone(_) => {}
            }
        }
        for tag in &self.touching {
            if let Tag::Edge(side) = *tag
                && !now.contains(tag)
            {
                let line = match side {
                    Side::Left => &self.layout.left_edge,
                    Side::Right => &self.layout.right_edge,
                };
                let left_of = left_of_polyline(line, [pos.x_m, pos.y_m]);
                let off_road = match side {
                    Side::Left => left_of,
                    Side::Right => !left_of,
                };
                self.events.push(WorldEvent::EdgeCleared { side, off_road });
            }
        }
        // Keep both buffers (and their capacity) for the next step.
        self.touching_now = std::mem::replace(&mut self.touching, now);
    }
}

/// The tag of collider `h` in `tags` (sorted by handle).
fn tag_of(tags: &[(ColliderHandle, Tag)], h: ColliderHandle) -> Option<Tag> {
    tags.binary_search_by_key(&h.into_raw_parts(), |(c, _)| c.into_raw_parts())
        .ok()
        .map(|i| tags[i].1)
}

/// Whether `p` lies to the left of the nearest segment of `line`.
fn left_of_polyline(line: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut best = (f64::INFINITY, false);
    for w in line.windows(2) {
        let ([ax, ay], [bx, by]) = (w[0], w[1]);
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = (dx * dx + dy * dy).max(1e-12);
        let t = (((p[0] - ax) * dx + (p[1] - ay) * dy) / len2).clamp(0.0, 1.0);
        let (qx, qy) = (ax + t * dx, ay + t * dy);
        let d2 = (p[0] - qx).powi(2) + (p[1] - qy).powi(2);
        if d2 < best.0 {
            best = (d2, dx * (p[1] - ay) - dy * (p[0] - ax) > 0.0);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference;

    /// Run the rapier world and the reference for 20 s at dt = 1 ms and return the largest
    /// position (m) and heading (deg) differences seen at each whole second.
    fn cross_check(inputs: impl Fn(f64) -> (f64, f64), breakpoints: &[f64]) -> (f64, f64) {
        let start = VehicleState {
            ux_m_s: 15.0,
            ..Default::default()
        };
        let mut world = World::new(
            VehicleParams::thesis_linear(),
            start,
            TrackLayout::default(),
        )
        .unwrap();
        let dt = 1e-3;
        let mut y = [0.0, 0.0, 0.0, 15.0, 0.0, 0.0];
        let (mut max_pos, mut max_yaw) = (0.0f64, 0.0f64);
        for sec in 1..=20 {
            let (t0, t1) = (f64::from(sec - 1), f64::from(sec));
            // Reference: split at input discontinuities inside this second.
            let mut cuts = vec![t0];
            cuts.extend(breakpoints.iter().copied().filter(|b| *b > t0 && *b < t1));
            cuts.push(t1);
            for w in cuts.windows(2) {
                y = reference::integrate(y, w[0], w[1], &inputs);
            }
            for i in 0..1000 {
                // The world holds each input for a step: sample it at mid-step.
                let t = t0 + (f64::from(i) + 0.5) * dt;
                let (delta, fad) = inputs(t);
                world.step(
                    DriverInput {
                        steer_rad: delta,
                        drive_force_n: fad,
                        brake_force_n: 0.0,
                    },
                    dt,
                );
            }
            let s = world.state();
            max_pos = max_pos.max((s.x_m - y[0]).hypot(s.y_m - y[1]));
            max_yaw = max_yaw.max((s.yaw_rad - y[2]).abs().to_degrees());
        }
        eprintln!("cross-check: max position error {max_pos:.3e} m, heading {max_yaw:.3e} deg");
        (max_pos, max_yaw)
    }

    #[test]
    fn rapier_steady_cornering_matches_reference_within_2cm_and_0_2deg() {
        let (pos, yaw) = cross_check(|_| (0.03, 300.0), &[]);
        assert!(
            pos < 0.02 && yaw < 0.2,
            "position {pos} m, heading {yaw} deg"
        );
    }

    #[test]
    fn rapier_step_steer_matches_reference_within_2cm_and_0_2deg() {
        let (pos, yaw) = cross_check(|t| (if t < 1.0 { 0.0 } else { 0.02 }, 0.0), &[1.0]);
        assert!(
            pos < 0.02 && yaw < 0.2,
            "position {pos} m, heading {yaw} deg"
        );
    }

    #[test]
    fn rapier_sine_steer_matches_reference_within_2cm_and_0_2deg() {
        let (pos, yaw) = cross_check(
            |t| (0.04 * (std::f64::consts::TAU * 0.4 * t).sin(), 100.0),
            &[],
        );
        assert!(
            pos < 0.02 && yaw < 0.2,
            "position {pos} m, heading {yaw} deg"
        );
    }

    #[test]
    fn a_track_with_barriers_keeps_rapiers_pipeline() {
        let layout = TrackLayout {
            barriers: vec![vec![[20.0, -10.0], [20.0, 10.0]]],
            ..Default::default()
        };
        let world = World::new(VehicleParams::default(), VehicleState::default(), layout).unwrap();
        assert!(matches!(world.motion, Motion::Solver));
    }

    #[test]
    fn barrier_stops_the_car() {
        let layout = TrackLayout {
            barriers: vec![vec![[20.0, -10.0], [20.0, 10.0]]],
            ..Default::default()
        };
        let start = VehicleState {
            ux_m_s: 5.0,
            ..Default::default()
        };
        let mut world = World::new(VehicleParams::default(), start, layout).unwrap();
        let mut events = Vec::new();
        for _ in 0..8000 {
            world.step(DriverInput::default(), 1e-3);
            events.extend(world.drain_events());
        }
        let s = world.state();
        assert!(events.contains(&WorldEvent::BarrierHit));
        let front = s.x_m + (VehicleParams::default().body_length_m / 2.0 + 0.03);
        assert!(front < 20.2 && s.ux_m_s.abs() < 0.5, "{s:?}");
    }
}
