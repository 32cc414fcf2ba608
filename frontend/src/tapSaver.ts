/**
 * Every change of the taps PUTs the whole tap set, without ever losing a tap on a weak
 * network: one request at a time, the newest tap set wins, failures are retried with
 * backoff while the taps stay on the phone.
 *
 * A change goes at once, before the screen shows it (session/taps.ts): the answer reaches
 * the other phone one round trip after the tap.
 * Nothing waits for more changes to come, since every change is a placed one: a finger
 * that drags a landmark or aims with the loupe changes nothing until it lets go
 * (gestures.ts). Changes made while a PUT is on its way go together after it, the newest.
 */

import { errorText } from "./i18n/server";
import { ApiError } from "./api";
import { backoffDelay } from "./reconnect";
import type { SessionState, Taps } from "./types";

export type SaveStatus = "saved" | "saving" | "error";

export interface SaveState {
  status: SaveStatus;
  /** Why it failed (the server's sentence, or no connection). */
  message: string | null;
}

export interface TapSaverOptions {
  send: (taps: Taps) => Promise<SessionState>;
  /** The server's state after a saved change (with the answer recomputed). */
  onSaved: (state: SessionState) => void;
  onStatus: (state: SaveState) => void;
  /** The session is gone (401). */
  onEnded: () => void;
  /** A PUT came back (saved or not): nothing is in flight now. */
  onSettled?: () => void;
  delay?: (attempt: number) => number;
  setTimer?: (run: () => void, ms: number) => unknown;
  clearTimer?: (timer: unknown) => void;
}

export class TapSaver {
  private wanted: Taps | null = null;
  private sentJson: string | null = null;
  private wantedJson: string | null = null;
  private inFlight = false;
  private timer: unknown = null;
  private failures = 0;
  private held = false;
  private state: SaveState = { status: "saved", message: null };
  private readonly delay: (attempt: number) => number;
  private readonly setTimer: (run: () => void, ms: number) => unknown;
  private readonly clearTimer: (timer: unknown) => void;

  constructor(private readonly options: TapSaverOptions) {
    // At most ~4 s between tries: a phone back on the network saves within seconds even when
    // the browser says nothing of it (no "online" event after a dropped connection).
    this.delay = options.delay ?? ((attempt) => backoffDelay(attempt, { baseMs: 1000, maxMs: 4000 }));
    this.setTimer = options.setTimer ?? ((run, ms) => setTimeout(run, ms));
    this.clearTimer =
      options.clearTimer ?? ((timer) => clearTimeout(timer as ReturnType<typeof setTimeout>));
  }

  /** What the server has now (after loading the session): nothing to send for it. */
  saved(taps: Taps): void {
    this.sentJson = JSON.stringify(taps);
  }

  /** The phone's taps changed: send them now (a PUT on its way: after its reply). */
  update(taps: Taps): void {
    this.wanted = taps;
    this.wantedJson = JSON.stringify(taps);
    if (this.wantedJson === this.sentJson && !this.inFlight) {
      this.cancelTimer();
      this.setState({ status: "saved", message: null });
      return;
    }
    this.setState({ status: "saving", message: null });
    this.failures = 0;
    this.cancelTimer();
    void this.flush();
  }

  /** What the saver says now ("saving", "saved", an error). */
  get status(): SaveState {
    return this.state;
  }

  /** Whether some taps are not on the server yet. */
  get pending(): boolean {
    return this.wantedJson !== null && this.wantedJson !== this.sentJson;
  }

  /** Whether a PUT is on its way: its reply will be the newest state. */
  get sending(): boolean {
    return this.inFlight;
  }

  /**
   * Hold the taps on the phone (`true`: the photo they are on is not on the server yet, and
   * taps must never be sent for a photo it does not have), or send what waits (`false`).
   */
  hold(held: boolean): void {
    this.held = held;
    if (held) this.cancelTimer();
    else this.retryNow();
  }

  /** The network is back (or the person asked): try now. */
  retryNow(): void {
    if (this.pending && !this.inFlight) {
      this.failures = 0;
      this.setState({ status: "saving", message: null });
      this.schedule(0);
    }
  }

  stop(): void {
    this.cancelTimer();
    this.wanted = null;
    this.wantedJson = null;
  }

  private setState(state: SaveState): void {
    if (state.status !== this.state.status || state.message !== this.state.message) {
      this.state = state;
      this.options.onStatus(state);
    }
  }

  private cancelTimer(): void {
    if (this.timer !== null) this.clearTimer(this.timer);
    this.timer = null;
  }

  private schedule(ms: number): void {
    this.cancelTimer();
    this.timer = this.setTimer(() => {
      this.timer = null;
      void this.flush();
    }, ms);
  }

  private async flush(): Promise<void> {
    if (this.held || this.inFlight || this.wanted === null || !this.pending) return;
    const taps = this.wanted;
    const json = this.wantedJson;
    this.inFlight = true;
    try {
      const state = await this.options.send(taps);
      this.sentJson = json;
      this.failures = 0;
      this.inFlight = false;
      this.options.onSaved(state);
      this.options.onSettled?.();
      if (this.pending) this.schedule(0);
      else this.setState({ status: "saved", message: null });
    } catch (error) {
      this.inFlight = false;
      const refusal = error instanceof ApiError ? error : new ApiError(0, "network", String(error));
      if (refusal.sessionEnded) {
        this.options.onEnded();
        return;
      }
      this.options.onSettled?.();
      this.setState({ status: "error", message: errorText(refusal) });
      if (refusal.retryable) {
        this.schedule(this.delay(this.failures++));
      } else if (this.wantedJson !== json) {
        this.schedule(0); // refused, but the taps changed since: try the new ones
      }
      // Refused as it is (say a mark outside the photo): kept on the phone until changed.
    }
  }
}
