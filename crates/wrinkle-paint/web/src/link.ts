/**
 * The WebSocket `/api/ws` with flow control: messages that the server answers with a frame (camera,
 * stroke_point, stroke_end, undo, redo, frame) wait in a queue while an earlier one waits for its frame.
 * Queued camera moves are coalesced (only the newest is sent); stroke points are never dropped: the points
 * queued while a frame was pending are all sent, in order, when it arrives.
 */
export type Outgoing = { type: string; [field: string]: unknown };

export interface LinkHandlers {
  open(): void;
  close(): void;
  /** A binary frame, with the time from sending its message (null when none was waiting for it). */
  frame(blob: Blob, latencyMs: number | null): void;
  /** A text message (already parsed). */
  message(msg: { type?: string; [field: string]: unknown }): void;
}

/** Messages the server answers with a frame. */
const ANSWERED = new Set(['camera', 'stroke_point', 'stroke_end', 'undo', 'redo', 'frame']);
const RECONNECT_MS = 1000;
/** A frame not come after this long is taken as lost, so that the queue moves on. */
const FRAME_TIMEOUT_MS = 2000;

/** The MIME type of a frame from its first bytes: PNG starts 0x89 'P' 'N' 'G', JPEG 0xFF 0xD8. */
export function frameMime(bytes: Uint8Array): string | null {
  if (bytes.length >= 4 && bytes[0] === 0x89 && bytes[1] === 0x50 && bytes[2] === 0x4e && bytes[3] === 0x47) {
    return 'image/png';
  }
  if (bytes.length >= 2 && bytes[0] === 0xff && bytes[1] === 0xd8) return 'image/jpeg';
  return null;
}

export class Link {
  private ws: WebSocket | null = null;
  private queue: Outgoing[] = [];
  /** When each sent message still waiting for its frame was sent, oldest first. */
  private waiting: number[] = [];
  private reconnectTimer: number | undefined;

  constructor(
    private readonly url: string,
    private readonly on: LinkHandlers,
  ) {
    window.setInterval(() => this.checkTimeout(), 500);
  }

  get connected(): boolean {
    return this.ws !== null && this.ws.readyState === WebSocket.OPEN;
  }

  /** Whether a sent message still waits for its frame. */
  get pending(): boolean {
    return this.waiting.length > 0;
  }

  connect(): void {
    window.clearTimeout(this.reconnectTimer);
    const ws = new WebSocket(this.url);
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    ws.onopen = () => {
      if (this.ws !== ws) return;
      this.on.open();
      this.pump();
    };
    ws.onmessage = (ev: MessageEvent) => {
      if (this.ws !== ws) return;
      if (typeof ev.data === 'string') {
        let msg: { type?: string; [field: string]: unknown };
        try {
          msg = JSON.parse(ev.data);
        } catch {
          this.on.message({ type: 'error', message: `unreadable message from the server: ${ev.data.slice(0, 80)}` });
          return;
        }
        // An error answers a message in place of its frame: the queue moves on.
        if (msg.type === 'error' && this.waiting.length > 0) {
          this.waiting.shift();
          this.pump();
        }
        this.on.message(msg);
        return;
      }
      const bytes = new Uint8Array(ev.data as ArrayBuffer);
      const mime = frameMime(bytes);
      const sent = this.waiting.shift();
      const latency = sent === undefined ? null : performance.now() - sent;
      if (mime) {
        this.on.frame(new Blob([bytes], { type: mime }), latency);
      } else {
        this.on.message({ type: 'error', message: 'a frame that is neither PNG nor JPEG' });
      }
      this.pump();
    };
    ws.onclose = () => {
      if (this.ws !== ws) return;
      this.ws = null;
      // What was queued belonged to the old connection (a stroke there has ended with it).
      this.queue = [];
      this.waiting = [];
      this.on.close();
      this.reconnectTimer = window.setTimeout(() => this.connect(), RECONNECT_MS);
    };
    ws.onerror = () => {
      // onclose follows and reconnects.
    };
  }

  /** Queues a message; sends it at once when no frame is pending. */
  send(msg: Outgoing): void {
    const last = this.queue[this.queue.length - 1];
    if (last && msg.type === 'camera' && last.type === 'camera') {
      this.queue[this.queue.length - 1] = msg;
    } else if (last && msg.type === 'frame' && last.type === 'frame') {
      this.queue[this.queue.length - 1] = { ...msg, lossless: Boolean(last.lossless) || Boolean(msg.lossless) };
    } else {
      this.queue.push(msg);
    }
    this.pump();
  }

  /** Drops the queued (not yet sent) messages. */
  clear(): void {
    this.queue = [];
  }

  private pump(): void {
    const ws = this.ws;
    if (!ws || ws.readyState !== WebSocket.OPEN) return;
    let sentPoints = false;
    while (this.queue.length > 0) {
      const msg = this.queue[0];
      const answered = ANSWERED.has(msg.type);
      if (answered && this.waiting.length > 0) {
        // A run of stroke points goes out together: none of them is held back behind another's frame.
        if (!(sentPoints && msg.type === 'stroke_point')) break;
      }
      this.queue.shift();
      ws.send(JSON.stringify(msg));
      if (answered) {
        this.waiting.push(performance.now());
        if (msg.type === 'stroke_point') sentPoints = true;
        else break;
      }
    }
  }

  private checkTimeout(): void {
    if (this.waiting.length > 0 && performance.now() - this.waiting[0] > FRAME_TIMEOUT_MS) {
      this.waiting = [];
      this.pump();
    }
  }
}
