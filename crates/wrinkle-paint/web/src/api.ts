/** The HTTP API of docs/paint.md that the page uses. */
import type { Camera } from './camera';

export interface PaintState {
  width: number;
  height: number;
  channels: unknown[];
  atlas_size: unknown;
  camera: Camera & { fov_y?: number; fov?: number };
  undo: number;
  redo: number;
  model?: unknown;
  [field: string]: unknown;
}

/** The error an answer names (`{"error": "..."}`), else its status. */
async function failure(res: Response): Promise<Error> {
  let text = `${res.status} ${res.statusText}`;
  try {
    const body = await res.json();
    if (body && typeof body.error === 'string') text = body.error;
  } catch {
    // not JSON: the status says it
  }
  return new Error(text);
}

export async function getJson<T>(path: string): Promise<T> {
  const res = await fetch(path, { cache: 'no-store' });
  if (!res.ok) throw await failure(res);
  return (await res.json()) as T;
}

export async function postJson<T>(path: string, body: unknown): Promise<T> {
  const res = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body ?? {}),
  });
  if (!res.ok) throw await failure(res);
  return (await res.json()) as T;
}

/** A channel's name, whether `channels` lists names or objects with a `name`. */
export function channelName(c: unknown): string | null {
  if (typeof c === 'string') return c;
  if (c && typeof c === 'object' && typeof (c as { name?: unknown }).name === 'string') {
    return (c as { name: string }).name;
  }
  return null;
}
