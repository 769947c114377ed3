/**
 * The orbit camera of the protocol: yaw about +y and pitch (elevation) in degrees, the eye at
 * target + distance * (cos(pitch) sin(yaw), sin(pitch), cos(pitch) cos(yaw)), looking at the target.
 */
export type Vec3 = [number, number, number];

export interface Camera {
  yaw: number;
  pitch: number;
  distance: number;
  target: Vec3;
}

const DEG = Math.PI / 180;
/** Pitch stays short of the poles, where yaw would be undefined. */
export const PITCH_LIMIT = 89;
/** Orbit speed: degrees per view pixel dragged. */
export const ORBIT_DEG_PER_PIXEL = 0.4;

export function clone(c: Camera): Camera {
  return { yaw: c.yaw, pitch: c.pitch, distance: c.distance, target: [c.target[0], c.target[1], c.target[2]] };
}

/** The unit vector from the target towards the eye. */
export function backward(c: Camera): Vec3 {
  const y = c.yaw * DEG;
  const p = c.pitch * DEG;
  return [Math.cos(p) * Math.sin(y), Math.sin(p), Math.cos(p) * Math.cos(y)];
}

/** The screen's right in world space: d(backward)/d(yaw), normalised; +x at yaw 0. */
export function right(c: Camera): Vec3 {
  const y = c.yaw * DEG;
  return [Math.cos(y), 0, -Math.sin(y)];
}

/** The screen's up in world space: d(backward)/d(pitch); +y at pitch 0. */
export function up(c: Camera): Vec3 {
  const y = c.yaw * DEG;
  const p = c.pitch * DEG;
  return [-Math.sin(p) * Math.sin(y), Math.cos(p), -Math.sin(p) * Math.cos(y)];
}

function wrapDegrees(a: number): number {
  const w = ((a + 180) % 360 + 360) % 360 - 180;
  return w === -180 ? 180 : w;
}

/** Drag right turns the model right (the eye moves left), drag down shows it from above. */
export function orbit(c: Camera, dxPixels: number, dyPixels: number): Camera {
  const n = clone(c);
  n.yaw = wrapDegrees(c.yaw - dxPixels * ORBIT_DEG_PER_PIXEL);
  n.pitch = Math.max(-PITCH_LIMIT, Math.min(PITCH_LIMIT, c.pitch + dyPixels * ORBIT_DEG_PER_PIXEL));
  return n;
}

/**
 * Moves the target in the camera plane so that the point under the mouse follows it: `dx`, `dy` in view
 * pixels (dy down), `viewHeight` the view's height in pixels, `fovY` the vertical field of view in degrees.
 */
export function pan(c: Camera, dxPixels: number, dyPixels: number, viewHeight: number, fovY: number): Camera {
  const perPixel = (2 * c.distance * Math.tan((fovY * DEG) / 2)) / Math.max(1, viewHeight);
  const r = right(c);
  const u = up(c);
  const n = clone(c);
  for (let i = 0; i < 3; i++) {
    n.target[i] = c.target[i] - r[i] * dxPixels * perPixel + u[i] * dyPixels * perPixel;
  }
  return n;
}

/** Each notch away (positive) multiplies the distance by 1.1, towards divides it; clamped to [min, max]. */
export function zoom(c: Camera, notches: number, min: number, max: number): Camera {
  const n = clone(c);
  n.distance = Math.max(min, Math.min(max, c.distance * Math.pow(1.1, notches)));
  return n;
}
