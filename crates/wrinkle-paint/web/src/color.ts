/** One sRGB-encoded component in 0..1 to linear light. */
export function srgbToLinear(c: number): number {
  return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
}

/** `#rrggbb` (what <input type=color> gives) to linear RGB floats, as the `color` brush field wants. */
export function hexToLinear(hex: string): [number, number, number] {
  const m = /^#?([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i.exec(hex.trim());
  if (!m) throw new Error(`not a colour: ${hex}`);
  const channel = (h: string) => srgbToLinear(parseInt(h, 16) / 255);
  return [channel(m[1]), channel(m[2]), channel(m[3])];
}
