/**
 * Staying in touch: the server's state of the session, kept current on this phone. Events
 * are taken in as they come (changes.ts), the state is fetched when they cannot tell
 * (reconnect.ts: one fetch at a time, the event stream and its reopening), and now and then
 * without them; the page shown again or the network back reopens the stream at once.
 */

import { errorText } from "../i18n/server";
import { ApiError, fetchState, eventsUrl, isRetryable } from "../api";
import { takeIn, type Change } from "../changes";
import { LiveStream, Refetcher } from "../reconnect";
import { keepState, loadKeptState } from "../storage";
import type { SessionState } from "../types";
import type { SharedParts } from "./parts";
import type { SessionView, ViewStore } from "./view";

/** How often the state is fetched without being told of a change, ms. */
const POLL_MS = 30_000;

export interface SyncParts extends SharedParts {
  /** The network may be back (online, the page shown again, the stream reopened). */
  onConnectionBack: () => void;
}

export class SessionSync {
  private readonly refetcher: Refetcher;
  private readonly stream: LiveStream;
  private loaded = false;
  private readonly cleanups: Array<() => void> = [];
  /** Changes told while this phone's own PUT was on its way: judged when its reply is in. */
  private readonly heldChanges: Change[] = [];

  constructor(
    private readonly store: ViewStore,
    private readonly parts: SyncParts,
  ) {
    this.refetcher = new Refetcher(() => this.load());
    this.stream = new LiveStream({
      url: eventsUrl(store.view.credentials),
      onChange: (change) => this.changed(change),
      onEnded: parts.onEnded,
      onStatus: (stream) => {
        this.store.set({ stream });
        // The stream is back: so is the network. What waits goes now, not at its backoff's end.
        if (stream === "up") parts.onConnectionBack();
      },
    });
  }

  private get view(): SessionView {
    return this.store.view;
  }

  start(): void {
    this.refetcher.request();
    this.stream.start();
    const onVisible = (): void => {
      if (document.visibilityState !== "visible") return;
      this.stream.wake();
      this.parts.onConnectionBack();
    };
    const onOnline = (): void => {
      this.stream.wake();
      this.parts.onConnectionBack();
    };
    const onOffline = (): void => this.stream.drop();
    document.addEventListener("visibilitychange", onVisible);
    window.addEventListener("online", onOnline);
    window.addEventListener("offline", onOffline);
    // Now and then, also without an event: a join code runs out silently, and a proxy may
    // hold events back.
    const poll = setInterval(() => {
      if (document.visibilityState === "visible") this.refetcher.request();
    }, POLL_MS);
    this.cleanups.push(
      () => clearInterval(poll),
      () => document.removeEventListener("visibilitychange", onVisible),
      () => window.removeEventListener("online", onOnline),
      () => window.removeEventListener("offline", onOffline),
    );
  }

  stop(): void {
    this.stream.stop();
    for (const cleanup of this.cleanups.splice(0)) cleanup();
  }

  /** Fetch the state (once more after the fetch on its way, if one is). */
  refetch(): void {
    this.refetcher.request();
  }

  /** This phone's own PUT has its reply: the changes told meanwhile are judged now. */
  releaseHeld(): void {
    this.changed(...this.heldChanges.splice(0));
  }

  /**
   * Something changed (`changes`, events with their data), or may have (none given: the
   * stream opened, the page came back): take the events in, or fetch the state when one
   * cannot be (a version missing, or an event that cannot tell). The phone's own change is
   * told by the stream before the reply to its PUT brings it with its answer: such news
   * waits for that reply, and is then shown already.
   */
  private changed(...changes: Array<Change | undefined>): void {
    if (changes.length === 0) return;
    if (this.parts.saver.sending && changes.every((change) => change !== undefined)) {
      this.heldChanges.push(...(changes as Change[]));
      return;
    }
    const before = this.view.state;
    let state = before;
    let fetch = false;
    for (const change of changes) {
      const outcome = change ? takeIn(state, change) : ({ kind: "fetch" } as const);
      if (outcome.kind === "fetch") {
        fetch = true;
        break; // what comes after a gap is for the fetched state to show
      }
      if (outcome.kind === "applied") state = outcome.state;
    }
    if (state && state !== before) this.applyState(state);
    // A fetch on its way may have read before a change taken in here without a new version
    // (a phone came or went): it would show that change undone, so one more follows it.
    if (fetch || (state !== before && this.refetcher.busy)) this.refetcher.request();
  }

  private async load(): Promise<void> {
    if (this.view.ended) return;
    try {
      this.applyState(await fetchState(this.view.credentials));
    } catch (error) {
      if (error instanceof ApiError && error.sessionEnded) this.parts.onEnded();
      else if (!this.view.state) {
        // No signal since the page (re)loaded: the last state this phone saw, marked as
        // such, rather than an error; the stream's reconnecting brings the server's.
        const kept = isRetryable(error) ? loadKeptState(this.view.credentials.session_id) : null;
        if (kept) this.applyState(kept, true);
        else this.store.set({ loadError: errorText(error) });
      }
    }
  }

  /** Try loading again (the person tapped Retry). */
  reload(): void {
    this.store.set({ loadError: null });
    this.stream.wake();
  }

  /**
   * A state from the server (fetched, or the reply to a PUT): shown unless older. `kept`:
   * the phone's copy of the last one it saw (storage.ts), shown while there is no signal.
   */
  applyState(state: SessionState, kept = false): void {
    if (this.view.ended) return;
    const current = this.view.state;
    if (current && state.version < current.version) return; // an older answer arrived late
    const mine = state.photos[this.view.credentials.role];
    let extra: Partial<SessionView> = {};
    if (!this.loaded) {
      this.loaded = true;
      extra = { ...this.parts.taps.firstLoad(state), photo: mine ? { size: mine, key: `${state.version}` } : null };
    } else if (mine && !this.view.photo) {
      extra = { photo: { size: mine, key: `${state.version}` } };
    } else if (mine && this.view.kept && !this.view.photo?.pending) {
      // Back online after an offline start: the photo failed to load then; ask again.
      extra = { photo: { size: mine, key: `${state.version}-online` } };
    }
    if (!kept) keepState(this.view.credentials.session_id, state);
    this.store.set({ state, kept, loadError: null, ...this.parts.answer.patchFor(state), ...extra });
  }
}
