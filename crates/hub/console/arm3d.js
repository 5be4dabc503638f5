// The patient's arm and the wheel in 3-D (three.js), posed from the live summary: the grip on
// the rim at the wheel angle and the forearm's and upper arm's directions from their IMUs,
// drawn at the segment lengths the station was set up with. Drag (or the arrow keys with the
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
    this.scene.add(new THREE.AmbientLight(0xffffff, 1.2));
    const sun = new THREE.DirectionalLight(0xffffff, 2.0);
    sun.position.set(1, 2, 1.5);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.05, 10);
    this.yaw = 1.0; this.pitch = 0.35; this.distance = 1.9;

    const arm = new THREE.MeshStandardMaterial({ color: 0x0072b2 });
    const wheel = new THREE.MeshStandardMaterial({ color: 0xe69f00 });
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
    // The arm: two segments and three joints.
    this.upper = new THREE.Mesh(new THREE.CylinderGeometry(0.035, 0.03, 1, 16), arm);
    this.fore = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.025, 1, 16), arm);
    this.joints = [0.05, 0.045, 0.04].map(r => new THREE.Mesh(new THREE.SphereGeometry(r, 16, 12), arm));
    this.scene.add(this.upper, this.fore, ...this.joints);
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
    this.segment(this.upper, shoulder, elbow);
    this.segment(this.fore, elbow, grip);
    [shoulder, elbow, grip].forEach((p, i) => this.joints[i].position.copy(p));
    this.posed = true;
    this.draw();
    return true;
  }

  segment(mesh, from, to) {
    const d = to.clone().sub(from);
    mesh.position.copy(from).addScaledVector(d, 0.5);
    mesh.scale.set(1, d.length(), 1);
    mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), d.normalize());
  }

  draw() {
    const c = this.camera, r = this.distance;
    c.position.set(r * Math.sin(this.yaw) * Math.cos(this.pitch), r * Math.sin(this.pitch), r * Math.cos(this.yaw) * Math.cos(this.pitch));
    c.lookAt(0.05, 0.0, 0.2);
    this.renderer.render(this.scene, c);
  }
}
