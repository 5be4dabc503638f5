// The patient's arm and the wheel in 3-D (three.js), posed from the live summary: the grip on
// the rim at the wheel angle and the forearm's and upper arm's directions from their IMUs,
// drawn at the segment lengths the station was set up with, as a person's — upper arm, forearm
// and hand on the rim, with the shoulders, trunk and head beside them for context. Drag (or the arrow keys with the
// view focused) turns the camera around the wheel.
import * as THREE from '/console/vendor/three-0.181.2/three.module.min.js';

// The wheel frame of the station (x forward, y left, z up, metres) in three.js's (y up).
const toThree = (x, y, z) => new THREE.Vector3(-y, z, -x);

const GRIP_RADIUS_M = 0.14;
const WHEEL_TILT_RAD = 20 * Math.PI / 180;

export class ArmView {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setClearColor(0xf0f4f8);
    this.scene = new THREE.Scene();
    // Soft light: sky and floor, and a weak sun for the shapes' relief.
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x9aa3ad, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.1);
    sun.position.set(1, 2, 1.5);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.05, 10);
    this.yaw = 1.25; this.pitch = 0.3; this.distance = 2.2;

    const wheel = new THREE.MeshStandardMaterial({ color: 0xe69f00, roughness: 0.6 });
    // The wheel: a rim in its tilted plane and a spoke to the grip.
    this.wheelGroup = new THREE.Group();
    const rim = new THREE.Mesh(new THREE.TorusGeometry(GRIP_RADIUS_M, 0.012, 12, 64), wheel);
    this.spoke = new THREE.Mesh(new THREE.CylinderGeometry(0.008, 0.008, GRIP_RADIUS_M, 8), wheel);
    this.spoke.position.y = GRIP_RADIUS_M / 2;
    this.spokePivot = new THREE.Group();
    this.spokePivot.add(this.spoke);
    this.wheelGroup.add(rim, this.spokePivot);
    // The rim's plane: the wheel frame's y (left) and its tilted "up"; normal toward the patient.
    const up = toThree(-Math.sin(WHEEL_TILT_RAD), 0, Math.cos(WHEEL_TILT_RAD));
    const left = toThree(0, 1, 0);
    const normal = new THREE.Vector3().crossVectors(left, up).normalize();
    this.wheelGroup.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(left.clone().negate(), up, normal.clone().negate()));
    this.scene.add(this.wheelGroup);
    this.person = new Person();
    this.scene.add(this.person.group);
    this.scene.add(new THREE.GridHelper(2, 20, 0xb0b0b0, 0xd8d8d8).translateY(-0.6));
    this.posed = false;
    this.bindCamera();
    this.resize();
    window.addEventListener('resize', () => this.resize());
    this.draw();
  }

  bindCamera() {
    let drag = null;
    this.canvas.addEventListener('pointerdown', e => { drag = { x: e.clientX, y: e.clientY }; this.canvas.setPointerCapture(e.pointerId); });
    this.canvas.addEventListener('pointerup', () => { drag = null; });
    this.canvas.addEventListener('pointermove', e => {
      if (!drag) return;
      this.turn((e.clientX - drag.x) * 0.01, (e.clientY - drag.y) * 0.01);
      drag = { x: e.clientX, y: e.clientY };
    });
    this.canvas.addEventListener('wheel', e => { e.preventDefault(); this.distance = Math.min(4, Math.max(0.5, this.distance * (1 + e.deltaY * 0.001))); this.draw(); }, { passive: false });
    this.canvas.addEventListener('keydown', e => {
      const step = { ArrowLeft: [-0.1, 0], ArrowRight: [0.1, 0], ArrowUp: [0, -0.1], ArrowDown: [0, 0.1] }[e.key];
      if (step) { e.preventDefault(); this.turn(...step); }
    });
  }

  turn(dYaw, dPitch) {
    this.yaw += dYaw;
    this.pitch = Math.min(1.4, Math.max(-0.2, this.pitch + dPitch));
    this.draw();
  }

  resize() {
    const w = this.canvas.clientWidth || 600, h = this.canvas.clientHeight || 320;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.draw();
  }

  /** Pose from a live summary's `extra`; false when it carries no arm. */
  pose(extra) {
    const wheelAngle = extra.wheel_angle_rad ?? 0;
    // The spoke points at the grip: "right" at angle 0, turning toward "up" (to the left).
    this.spokePivot.rotation.z = wheelAngle - Math.PI / 2;
    if (extra.grip_m_x === undefined || extra.upper_axis_x === undefined) { this.draw(); return false; }
    const grip = toThree(extra.grip_m_x, extra.grip_m_y, extra.grip_m_z);
    const foreDir = toThree(extra.fore_axis_x, extra.fore_axis_y, extra.fore_axis_z);
    const upperDir = toThree(extra.upper_axis_x, extra.upper_axis_y, extra.upper_axis_z);
    if (foreDir.length() < 0.5 || upperDir.length() < 0.5) { this.draw(); return false; }
    const elbow = grip.clone().addScaledVector(foreDir, -(extra.forearm_m ?? 0.33));
    const shoulder = elbow.clone().addScaledVector(upperDir, -(extra.upper_arm_m ?? 0.30));
    this.person.pose(shoulder, elbow, grip, foreDir);
    this.posed = true;
    this.draw();
    return true;
  }

  draw() {
    const c = this.camera, r = this.distance;
    c.position.set(r * Math.sin(this.yaw) * Math.cos(this.pitch), r * Math.sin(this.pitch), r * Math.cos(this.yaw) * Math.cos(this.pitch));
    c.lookAt(0.0, -0.05, 0.3);
    this.renderer.render(this.scene, c);
  }
}

/** Puts `mesh` (a unit-long shape along y) from `from` to `to`. */
function segment(mesh, from, to) {
  const d = to.clone().sub(from);
  mesh.position.copy(from).addScaledVector(d, 0.5);
  mesh.scale.set(1, d.length(), 1);
  mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), d.normalize());
}

/**
 * The patient as simple shapes: trunk, head and both shoulders for context, and the measured
 * arm — upper arm in a sleeve, forearm and hand on the rim — as capsules (cylinders with
 * rounded joints). Only the arm is measured; the trunk is placed beside its shoulder.
 */
class Person {
  constructor() {
    const skin = new THREE.MeshStandardMaterial({ color: 0xd9a88a, roughness: 0.8 });
    const shirt = new THREE.MeshStandardMaterial({ color: 0x5b8fc7, roughness: 0.9 });
    const trunkShirt = new THREE.MeshStandardMaterial({ color: 0x5b8fc7, roughness: 0.9, transparent: true, opacity: 0.85 });
    this.group = new THREE.Group();
    this.group.visible = false;
    this.trunk = new THREE.Mesh(new THREE.BoxGeometry(0.36, 0.5, 0.2), trunkShirt);
    this.neck = new THREE.Mesh(new THREE.CylinderGeometry(0.045, 0.05, 0.08, 16), skin);
    this.head = new THREE.Mesh(new THREE.SphereGeometry(0.095, 24, 16), skin);
    this.head.scale.set(0.9, 1.1, 1);
    this.otherShoulder = new THREE.Mesh(new THREE.SphereGeometry(0.06, 16, 12), shirt);
    this.shoulder = new THREE.Mesh(new THREE.SphereGeometry(0.06, 16, 12), shirt);
    this.upper = new THREE.Mesh(new THREE.CylinderGeometry(0.05, 0.043, 1, 20), shirt);
    this.elbow = new THREE.Mesh(new THREE.SphereGeometry(0.042, 16, 12), skin);
    this.fore = new THREE.Mesh(new THREE.CylinderGeometry(0.04, 0.031, 1, 20), skin);
    this.wrist = new THREE.Mesh(new THREE.SphereGeometry(0.032, 16, 12), skin);
    this.hand = new THREE.Mesh(new THREE.SphereGeometry(0.05, 20, 14), skin);
    this.hand.scale.set(0.85, 1.35, 0.5);
    this.group.add(this.trunk, this.neck, this.head, this.otherShoulder, this.shoulder, this.upper,
                   this.elbow, this.fore, this.wrist, this.hand);
  }

  /** Poses the arm from its joints (three.js frame) and puts the trunk behind its shoulder. */
  pose(shoulder, elbow, grip, foreDir) {
    // The trunk's middle is toward the body's midline from the measured shoulder: a right arm
    // (its shoulder to the wheel's right, three.js +x) has the trunk to its left.
    const inward = shoulder.x >= 0 ? -1 : 1;
    const mid = new THREE.Vector3(shoulder.x + inward * 0.18, shoulder.y, shoulder.z + 0.04);
    this.trunk.position.set(mid.x, mid.y - 0.27, mid.z);
    this.neck.position.set(mid.x, mid.y + 0.04, mid.z);
    this.head.position.set(mid.x, mid.y + 0.17, mid.z);
    this.otherShoulder.position.set(mid.x + inward * 0.18, shoulder.y - 0.01, shoulder.z + 0.04);
    this.shoulder.position.copy(shoulder);
    segment(this.upper, shoulder, elbow);
    this.elbow.position.copy(elbow);
    const wrist = grip.clone().addScaledVector(foreDir, -0.05);
    segment(this.fore, elbow, wrist);
    this.wrist.position.copy(wrist);
    // The hand closed on the rim: its length along the forearm, centred on the grip.
    this.hand.position.copy(grip).addScaledVector(foreDir, 0.01);
    this.hand.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), foreDir.clone().normalize());
    this.group.visible = true;
  }
}
