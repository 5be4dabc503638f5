//! The car between contacts, moved without rapier's pipeline: the haptic thread's path.
//!
//! rapier2d 0.36 allocates on every step (its island manager when a body is changed from
//! outside, its island solver and its contact graph), and the 1 kHz thread must not. On a
//! track with no solid barrier the car never meets a solid contact, so a step needs only what
//! rapier's solver does to a free body and what its narrow phase says of the sensors. This
//! module does exactly that, in the same arithmetic, and allocates nothing:
//!
//! - [`FreeCar::kick`] is `RigidBody::apply_impulse` / `apply_torque_impulse` (the impulse
//!   times the body's effective inverse mass and inertia);
//! - [`FreeCar::drift`] is the staged island solver on a body with no constraint: the zero
//!   external-force increment, rapier's speed caps, the linearised rotation it integrates
//!   (`RigidBodyVelocity::integrate_linearized`: the unit complex turned by `ω·dt` and
//!   renormalised) and the translation `x += v·dt`;
//! - [`Sensors::touching`] is its narrow phase for sensor pairs: parry's intersection test
//!   of the car's box against each edge chunk and cone whose bounding box it overlaps, with
//!   the poses the step starts from (rapier detects collisions before it integrates).
//!
//! The test `the_free_car_moves_bit_for_bit_as_rapiers_solver_moves_it` holds both to rapier
//! over whole exercises: same poses, same velocities, same events, to the last bit. A track
//! with barriers keeps rapier's pipeline ([`super::World`]).

use rapier2d_f64::parry::bounding_volume::Aabb;
use rapier2d_f64::parry::math::{Pose, Rot2, Vector};
use rapier2d_f64::parry::partitioning::{Bvh, BvhBuildStrategy};
use rapier2d_f64::parry::query;
use rapier2d_f64::prelude::{ColliderHandle, ColliderSet, IntegrationParameters, RigidBody};

/// rapier's cap on a body's rotation per step, rad (`staged_island_solver::worker`).
const MAX_ROTATION_RAD: f64 = std::f64::consts::FRAC_PI_4;

/// The car's rigid-body state as rapier's solver keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FreeCar {
    /// Position of the body origin (the CG), m.
    pub translation: Vector,
    /// Heading as a unit complex number.
    pub rotation: Rot2,
    /// World-frame velocity, m/s.
    pub linvel: Vector,
    /// Yaw rate, rad/s.
    pub angvel: f64,
    /// The body's effective inverse mass, per axis, 1/kg (rapier's, read once).
    inv_mass: Vector,
    /// The body's effective inverse yaw inertia, 1/(kg·m²) (rapier's, read once).
    inv_inertia: f64,
}

impl FreeCar {
    /// The state and mass properties of rapier's `body`.
    pub fn of(body: &RigidBody) -> Self {
        let mprops = body.mass_properties();
        Self {
            translation: body.translation(),
            rotation: *body.rotation(),
            linvel: body.linvel(),
            angvel: body.angvel(),
            inv_mass: mprops.effective_inv_mass,
            inv_inertia: mprops.effective_world_inv_inertia,
        }
    }

    /// The body's pose.
    pub fn pose(&self) -> Pose {
        Pose::from_parts(self.translation, self.rotation)
    }

    /// Apply the linear `impulse` (N·s) and the angular `torque_impulse` (N·m·s), as
    /// `RigidBody::apply_impulse` and `apply_torque_impulse` do (a zero one does nothing).
    pub fn kick(&mut self, impulse: Vector, torque_impulse: f64) {
        if impulse != Vector::ZERO {
            self.linvel += impulse * self.inv_mass;
        }
        if torque_impulse != 0.0 {
            self.angvel += self.inv_inertia * torque_impulse;
        }
    }

    /// Move the body for one step of `params.dt` with no constraint acting on it, as rapier's
    /// staged island solver does with one solver iteration (module docs).
    pub fn drift(&mut self, params: &IntegrationParameters) {
        let dt = params.dt;
        // The increment of the external forces: none act (zero gravity, no user force).
        self.linvel += Vector::ZERO * self.inv_mass * dt;
        self.angvel += self.inv_inertia * 0.0 * dt;
        let max_lin = params.max_linear_velocity();
        if max_lin != f64::MAX {
            let n = self.linvel.length();
            if n > max_lin {
                self.linvel *= max_lin / n;
            }
        }
        let max_ang = MAX_ROTATION_RAD * params.inv_dt();
        if self.angvel.abs() > max_ang {
            self.angvel = self.angvel.signum() * max_ang;
        }
        let dang = self.angvel * dt;
        let rotation = self.rotation;
        let new_cos = rotation.re - dang * rotation.im;
        let new_sin = rotation.im + dang * rotation.re;
        let mut turned = Rot2::from_cos_sin_unchecked(new_cos, new_sin);
        turned.normalize_mut();
        self.rotation = turned;
        self.translation += self.linvel * dt;
        // The writeback's damping: none is set, `v·1/(1 + dt·0)`.
        self.linvel *= 1.0 / (1.0 + dt * 0.0);
        self.angvel *= 1.0 / (1.0 + dt * 0.0);
    }
}

/// The track's sensors (edge chunks and cones) as the free path queries them: a bounding-box
/// tree over the fixed colliders, built once, so a step's look-up costs the logarithm of the
/// track's length (a 200-period sine road has ~50 000 edge chunks) and allocates nothing (parry
/// walks it with a stack on the stack).
pub(super) struct Sensors {
    tree: Box<Bvh>,
    /// The collider of each of the tree's leaves.
    handles: Vec<ColliderHandle>,
    /// The car's collider pose relative to the body.
    car_local: Pose,
}

impl Sensors {
    /// The sensors among `colliders` (the `handles` given), for a car whose collider sits at
    /// `car_local` on its body.
    pub fn new(
        colliders: &ColliderSet,
        handles: impl Iterator<Item = ColliderHandle>,
        car_local: Pose,
    ) -> Self {
        let handles: Vec<ColliderHandle> = handles.collect();
        let boxes: Vec<Aabb> = handles
            .iter()
            .map(|h| colliders[*h].compute_aabb())
            .collect();
        Self {
            tree: Box::new(Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes)),
            handles,
            car_local,
        }
    }

    /// The sensors the car's box (`car_shape`, body at `body_pose`) intersects, each passed to
    /// `touch` (in the tree's order: the caller sorts what it keeps).
    pub fn touching(
        &self,
        colliders: &ColliderSet,
        car_shape: &dyn rapier2d_f64::parry::shape::Shape,
        body_pose: &Pose,
        mut touch: impl FnMut(ColliderHandle),
    ) {
        let car_pose = *body_pose * self.car_local;
        let car_box = car_shape.compute_aabb(&car_pose);
        for leaf in self.tree.intersect_aabb(&car_box) {
            let h = self.handles[leaf as usize];
            let co = &colliders[h];
            let hit = query::intersection_test(&car_pose, car_shape, co.position(), co.shape())
                .is_ok_and(|hit| hit.intersecting);
            if hit {
                touch(h);
            }
        }
    }
}
