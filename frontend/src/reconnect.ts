/**
 * Staying in touch over a weak network: backoff between retries, one state fetch at a time,
 * and the event stream of the session's changes (EventSource), reopened when it closes.
 *
 * Each change's event carries what the phone needs to show it (changes.ts takes it in). The
 * phone fetches the whole state when an event cannot tell, when the stream (re)opens (it may
 * have missed something while down), when the page becomes visible again and when the
 * network comes back.
 */

import type { Change } from "./changes";
import { EVENTS } from "./limits";

export interface BackoffOptions {
  /** First delay, ms. */
  baseMs?: number;
  /** Longest delay, ms. */
  maxMs?: number;
  /** Spread: each delay is multiplied by a factor in [1 - jitter, 1 + jitter]. */
  jitter?: number;
  random?: () => number;
}

/** Delay before retry number `attempt` (0 = the first retry): doubling, capped, jittered. */
export function backoffDelay(attempt: number, options: BackoffOptions = {}): number {
  const { baseMs = 1000, maxMs = 30_000, jitter = 0.2, random = Math.random } = options;
  const plain = Math.min(maxMs, baseMs * 2 ** Math.max(0, attempt));
  const factor = 1 - jitter + 2 * jitter * random();
  return Math.round(Math.min(maxMs, plain * factor));
}

export interface RetryOptions {
  /** How many times to try again after the first failure. */
  retries: number;
  /** Whether an error is worth another try (a network error is; a refusal is not). */
  isRetryable: (error: unknown) => boolean;
  delay?: (attempt: number) => number;
  sleep?: (ms: number) => Promise<void>;
}

export const sleep = (ms: number): Promise<void> => new Promise((done) => setTimeout(done, ms));

/** Run `task`; on a retryable error wait and run it again, up to `retries` more times. */
export async function withRetry<T>(
  task: (attempt: number) => Promise<T>,
  { retries, isRetryable, delay = backoffDelay, sleep: wait = sleep }: RetryOptions,
): Promise<T> {
  for (let attempt = 0; ; attempt++) {
    try {
      return await task(attempt);
    } catch (error) {
      if (attempt >= retries || !isRetryable(error)) throw error;
      await wait(delay(attempt));
    }
  }
}

/**
 * One fetch at a time: asking while one runs asks for one more afterwards (its answer may
 * predate the change), however many times it is asked meanwhile.
 */
export class Refetcher {
  private running = false;
  private again = false;

  constructor(private readonly fetch: () => Promise<void>) {}

  /** Whether a fetch is on its way (its answer may predate what is shown meanwhile). */
  get busy(): boolean {
    return this.running;
  }

  request(): void {
    if (this.running) {
      this.again = true;
      return;
    }
    void this.run();
  }

  private async run(): Promise<void> {
    this.running = true;
    try {
      do {
        this.again = false;
        try {
          await this.fetch();
        } catch {
          // the caller's fetch reports its own errors; the next change asks again
        }
      } while (this.again);
    } finally {
      this.running = false;
    }
  }
}

/** The event that ends the session on this phone; every other type the server sends
 * (limits.json's "events") says that something changed. */
export const ENDED_EVENT = "expired";
export const CHANGE_EVENTS: readonly string[] = EVENTS.filter((type) => type !== ENDED_EVENT);

export type StreamStatus = "connecting" | "up" | "down";

/** The part of EventSource this module uses (a fake in the tests). */
export interface EventSourceLike {
  readonly readyState: number;
  onopen: ((event: Event) => void) | null;
  onerror: ((event: Event) => void) | null;
  addEventListener(type: string, listener: (event: Event) => void): void;
  close(): void;
}

/** An event: its type, and its data parsed (null when it is not JSON). */
function changeOf(type: string, event: Event): Change {
  try {
    return { type, data: JSON.parse((event as MessageEvent<string>).data) as unknown };
  } catch {
    return { type, data: null };
  }
}

export interface LiveStreamOptions {
  url: string;
  /** Something changed (`change`, an event with its data), or may have (none: the stream
   * opened, the page came back: fetch the state). */
  onChange: (change?: Change) => void;
  /** The session ended (deleted by a phone, or timed out). */
  onEnded: () => void;
  onStatus: (status: StreamStatus) => void;
  open?: (url: string) => EventSourceLike;
  delay?: (attempt: number) => number;
  setTimer?: (run: () => void, ms: number) => unknown;
  clearTimer?: (timer: unknown) => void;
}

const CLOSED = 2;

/**
 * The session's event stream. EventSource reconnects by itself after a dropped connection
 * (resending Last-Event-ID); when it gives up (readyState CLOSED: an HTTP error, or the
 * server refused) a new one is opened after a backoff. Every (re)open fetches the state.
 */
export class LiveStream {
  private source: EventSourceLike | null = null;
  private timer: unknown = null;
  private failures = 0;
  private stopped = false;
  private status: StreamStatus = "connecting";
  private readonly open: (url: string) => EventSourceLike;
  private readonly delay: (attempt: number) => number;
  private readonly setTimer: (run: () => void, ms: number) => unknown;
  private readonly clearTimer: (timer: unknown) => void;

  constructor(private readonly options: LiveStreamOptions) {
    // The browser's own EventSource: a maintained client (reconnects, resends Last-Event-ID).
    this.open = options.open ?? ((url) => new EventSource(url));
    // Capped at ~4 s: a phone back on the network (or a restarted server) is caught up
    // within seconds; a reopen is one small request.
    this.delay = options.delay ?? ((attempt) => backoffDelay(attempt, { baseMs: 2000, maxMs: 4000 }));
    this.setTimer = options.setTimer ?? ((run, ms) => setTimeout(run, ms));
    this.clearTimer =
      options.clearTimer ?? ((timer) => clearTimeout(timer as ReturnType<typeof setTimeout>));
  }

  start(): void {
    this.stopped = false;
    this.connect();
  }

  stop(): void {
    this.stopped = true;
    if (this.timer !== null) this.clearTimer(this.timer);
    this.timer = null;
    this.source?.close();
    this.source = null;
  }

  /**
   * The browser says the network is gone: the stream over it is dead, even when its
   * connection has not noticed yet (a dropped network may close nothing). Down until
   * `wake` (the network back, the page shown again).
   */
  drop(): void {
    if (this.stopped) return;
    if (this.timer !== null) this.clearTimer(this.timer);
    this.timer = null;
    this.source?.close();
    this.source = null;
    this.setStatus("down");
  }

  /** The page is visible again, or the network is back: fetch, and reopen a dead stream. */
  wake(): void {
    if (this.stopped) return;
    this.options.onChange();
    if (this.source === null || this.source.readyState === CLOSED) {
      if (this.timer !== null) this.clearTimer(this.timer);
      this.timer = null;
      this.failures = 0;
      this.connect();
    }
  }

  private setStatus(status: StreamStatus): void {
    if (status !== this.status) {
      this.status = status;
      this.options.onStatus(status);
    }
  }

  private connect(): void {
    if (this.stopped) return;
    this.source?.close();
    const source = this.open(this.options.url);
    this.source = source;
    source.onopen = () => {
      if (this.source !== source) return;
      this.failures = 0;
      this.setStatus("up");
      this.options.onChange();
    };
    source.onerror = () => {
      if (this.source !== source || this.stopped) return;
      this.setStatus("down");
      if (source.readyState === CLOSED) {
        source.close();
        this.source = null;
        // Maybe the session is gone (401): the state fetch finds out.
        this.options.onChange();
        const wait = this.delay(this.failures++);
        this.timer = this.setTimer(() => {
          this.timer = null;
          this.connect();
        }, wait);
      }
    };
    for (const type of CHANGE_EVENTS) {
      source.addEventListener(type, (event) => {
        if (this.source === source) this.options.onChange(changeOf(type, event));
      });
    }
    source.addEventListener(ENDED_EVENT, () => {
      if (this.source !== source) return;
      this.stop();
      this.options.onEnded();
    });
  }
}
