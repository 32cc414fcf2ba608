/**
 * One phone in one session: the server's state, this phone's taps, saving them, the photo
 * upload and the event stream. Components read `view` and call the actions; nothing here
 * draws.
 */

import {
  ApiError,
  deleteSession,
  eventsUrl,
  fetchState,
  isRetryable,
  putTaps,
} from "./api";
import { browserDecoder, preparePhoto, type PreparedPhoto } from "./downscale";
import {
  addLandmark,
  deleteLandmark,
  friendMarked,
  fromServerTaps,
  landmarkIds,
  lineThrough,
  moveLandmark,
  newEditor,
  select,
  setFriend,
  setFriendLine,
  toServerTaps,
  undo,
  type TapEditor,
} from "./landmarks";
import { readLens } from "./lens";
import { lineSigma } from "./precision";
import { takeIn, type Change } from "./changes";
import { LiveStream, Refetcher, type StreamStatus } from "./reconnect";
import { forgetSession, loadDraft, saveDraft } from "./storage";
import { TapSaver, type SaveState } from "./tapSaver";
import { otherRole, type Credentials, type LensFields, type SessionState } from "./types";
import { localPhoto, scaleTaps, sendPhoto, type ShownPhoto } from "./upload";
import type { Point } from "./viewTransform";

/** What a tap on the photo places: the friend, a point of a line through them, a landmark. */
export type Mode = "friend" | "line" | "landmark";

/** A tap on the photo: where (photo px), and how precise (sigma, photo px: precision.ts). */
export interface Tap extends Point {
  readonly sigma: number;
}

export interface UploadState {
  phase: "idle" | "preparing" | "uploading" | "failed";
  /** 0..1 while uploading. */
  progress: number;
  message: string | null;
  /** Whether Retry can help (no connection), or another photo is needed (refused). */
  retryable: boolean;
}

export type Ending = "deleted" | "ended";

export interface SessionView {
  readonly credentials: Credentials;
  readonly state: SessionState | null;
  /** The state with the latest answer shown (held briefly while an answer is renewed). */
  readonly answerState: SessionState | null;
  readonly loadError: string | null;
  readonly editor: TapEditor;
  readonly skipped: ReadonlySet<number>;
  /** This phone said it cannot see the friend: it is not asked again for this photo. */
  readonly unseen: boolean;
  readonly mode: Mode;
  /** The first point of a line through the friend, until the second is tapped. */
  readonly linePoint: Tap | null;
  readonly save: SaveState;
  readonly stream: StreamStatus;
  readonly upload: UploadState;
  readonly ended: Ending | null;
  /** This phone's photo: the stored one, or its own copy while it is sent (upload.ts). */
  readonly photo: ShownPhoto | null;
  readonly deleteError: string | null;
}

const IDLE_UPLOAD: UploadState = { phase: "idle", progress: 0, message: null, retryable: false };
/** How often the state is fetched without being told of a change, ms. */
const POLL_MS = 30_000;
/** How long an answer stays on screen while the next one is being computed. */
const ANSWER_HOLD_MS = 2500;

export class SessionController {
  view: SessionView;
  private readonly listeners = new Set<() => void>();
  private readonly saver: TapSaver;
  private readonly refetcher: Refetcher;
  private readonly stream: LiveStream;
  private loaded = false;
  private prepared: (PreparedPhoto & { lens: LensFields }) | null = null;
  /** What was on screen before a new photo was shown: back to it if that photo is refused. */
  private before: Pick<SessionView, "photo" | "editor" | "unseen" | "mode"> | null = null;
  private holdTimer: ReturnType<typeof setTimeout> | null = null;
  private readonly cleanups: Array<() => void> = [];
  /** Changes told while this phone's own PUT was on its way: judged when its reply is in. */
  private readonly heldChanges: Change[] = [];

  constructor(credentials: Credentials) {
    this.view = {
      credentials,
      state: null,
      answerState: null,
      loadError: null,
      editor: newEditor(),
      skipped: new Set(),
      unseen: false,
      mode: "friend",
      linePoint: null,
      save: { status: "saved", message: null },
      stream: "connecting",
      upload: IDLE_UPLOAD,
      ended: null,
      photo: null,
      deleteError: null,
    };
    this.saver = new TapSaver({
      send: (taps) => putTaps(credentials, taps),
      onSaved: (state) => {
        this.keepDraft();
        this.applyState(state);
      },
      onStatus: (save) => this.set({ save }),
      onEnded: () => this.end("ended"),
      onSettled: () => this.changed(...this.heldChanges.splice(0)),
    });
    this.refetcher = new Refetcher(() => this.load());
    this.stream = new LiveStream({
      url: eventsUrl(credentials),
      onChange: (change) => this.changed(change),
      onEnded: () => this.end("ended"),
      onStatus: (stream) => {
        this.set({ stream });
        // The stream is back: so is the network. What waits goes now, not at its backoff's end.
        if (stream === "up") this.connectionBack();
      },
    });
  }

  get role(): Credentials["role"] {
    return this.view.credentials.role;
  }

  subscribe(listener: () => void): () => void {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  private set(patch: Partial<SessionView>): void {
    this.view = { ...this.view, ...patch };
    for (const listener of this.listeners) listener();
  }

  // --- staying in touch --------------------------------------------------------------------

  start(): void {
    this.refetcher.request();
    this.stream.start();
    const onVisible = (): void => {
      if (document.visibilityState !== "visible") return;
      this.stream.wake();
      this.connectionBack();
    };
    const onOnline = (): void => {
      this.stream.wake();
      this.connectionBack();
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

  /** The network may be back (online, the page shown again, the stream reopened): send the
   * taps and the photo that wait, at once. */
  private connectionBack(): void {
    this.saver.retryNow();
    if (this.view.upload.phase === "failed" && this.view.upload.retryable) void this.retryUpload();
  }

  stop(): void {
    this.forgetLocal(this.view.photo);
    this.stream.stop();
    this.saver.stop();
    if (this.holdTimer) clearTimeout(this.holdTimer);
    for (const cleanup of this.cleanups.splice(0)) cleanup();
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
    if (this.saver.sending && changes.every((change) => change !== undefined)) {
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
      if (error instanceof ApiError && error.sessionEnded) this.end("ended");
      else if (!this.view.state) {
        this.set({ loadError: error instanceof Error ? error.message : String(error) });
      }
    }
  }

  /** Try loading again (the person tapped Retry). */
  reload(): void {
    this.set({ loadError: null });
    this.stream.wake();
  }

  private applyState(state: SessionState): void {
    if (this.view.ended) return;
    const current = this.view.state;
    if (current && state.version < current.version) return; // an older answer arrived late
    const mine = state.photos[this.role];
    let extra: Partial<SessionView> = {};
    if (!this.loaded) {
      this.loaded = true;
      extra = this.firstLoad(state);
    } else if (mine && !this.view.photo) {
      extra = { photo: { size: mine, key: `${state.version}` } };
    }
    this.set({ state, loadError: null, ...this.answerPatch(this.forScreen(state)), ...extra });
  }

  /** The state to draw the answer from: none while a new photo is on its way (the answer of
   * the photo it replaces does not belong on it). */
  private forScreen(state: SessionState): SessionState {
    return this.view.photo?.pending ? { ...state, answer: null, answer_error: null } : state;
  }

  /** The taps to start from: unsaved ones kept on this phone, else the server's. */
  private firstLoad(state: SessionState): Partial<SessionView> {
    const server = state.taps[this.role];
    const draft = loadDraft(this.view.credentials.session_id);
    const mine = state.photos[this.role];
    this.saver.saved(toServerTaps(fromServerTaps(server)));
    let taps = fromServerTaps(server);
    if (draft?.unsaved && draft.taps && mine) {
      taps = fromServerTaps(draft.taps);
      this.saver.update(toServerTaps(taps));
    }
    const unseen = draft?.unseen ?? false;
    const patch: Partial<SessionView> = {
      editor: newEditor(taps),
      skipped: new Set(draft?.skipped ?? []),
      unseen,
      mode: startingMode(friendMarked(taps), unseen),
      photo: mine ? { size: mine, key: `${state.version}` } : null,
    };
    return patch;
  }

  /** Which state's answer to show: a missing answer while one is renewed is held a moment. */
  private answerPatch(state: SessionState): Partial<SessionView> {
    const hasAnswer = !!state.answer || !!state.answer_error;
    const shown = this.view.answerState;
    if (hasAnswer || !shown || (!shown.answer && !shown.answer_error)) {
      if (this.holdTimer) clearTimeout(this.holdTimer);
      this.holdTimer = null;
      return { answerState: state };
    }
    if (!this.holdTimer) {
      this.holdTimer = setTimeout(() => {
        this.holdTimer = null;
        this.set({ answerState: this.view.state && this.forScreen(this.view.state) });
      }, ANSWER_HOLD_MS);
    }
    return {};
  }

  private end(ending: Ending): void {
    if (this.view.ended) return;
    this.stop();
    forgetSession();
    this.set({ ended: ending });
  }

  // --- the photo ---------------------------------------------------------------------------

  /**
   * The lens is read from the chosen file itself: the shrunk copy keeps no EXIF. The shrunk
   * copy is shown and tapped on at once; the upload runs behind it (upload.ts).
   */
  async choosePhoto(file: File): Promise<void> {
    this.set({ upload: { ...IDLE_UPLOAD, phase: "preparing" } });
    const [lens, prepared] = await Promise.all([readLens(file), preparePhoto(file, browserDecoder())]);
    if (this.view.ended) return;
    this.prepared = { ...prepared, lens };
    const shown = localPhoto(prepared, `local-${Date.now()}`);
    if (shown) this.showNewPhoto(shown);
    await this.sendPrepared();
  }

  /** A new photo on screen before the server has it: new taps, held until it lands. */
  private showNewPhoto(photo: ShownPhoto): void {
    const { editor, unseen, mode } = this.view;
    if (!this.view.photo?.pending) this.before = { photo: this.view.photo, editor, unseen, mode };
    else this.forgetLocal(this.view.photo);
    this.saver.hold(true);
    this.set({
      photo,
      editor: newEditor(),
      unseen: false,
      mode: startingMode(false, false),
      linePoint: null,
    });
    // The answer of the photo it replaces goes at once (not held as a renewed answer is).
    if (this.holdTimer) clearTimeout(this.holdTimer);
    this.holdTimer = null;
    this.set({ answerState: this.view.state && this.forScreen(this.view.state) });
    // A reload meanwhile starts from the server's photo: nothing of this one is kept.
    saveDraft({ session_id: this.view.credentials.session_id, taps: null, unsaved: false, skipped: [...this.view.skipped], unseen: false });
  }

  private forgetLocal(photo: ShownPhoto | null): void {
    if (photo?.local) URL.revokeObjectURL(photo.local);
  }

  /** The person read the refusal: back to what was there. */
  dismissUpload(): void {
    this.prepared = null;
    const shown = this.view.photo;
    if (shown?.pending) {
      this.forgetLocal(shown);
      const before = this.before ?? { photo: null, editor: newEditor(), unseen: false, mode: startingMode(false, false) };
      this.before = null;
      this.saver.saved(toServerTaps(before.editor.taps));
      this.saver.hold(false);
      this.set({ ...before, linePoint: null, upload: IDLE_UPLOAD, save: { status: "saved", message: null } });
      this.keepDraft();
      this.refetcher.request();
      return;
    }
    this.set({ upload: IDLE_UPLOAD });
  }

  async retryUpload(): Promise<void> {
    if (this.prepared) await this.sendPrepared();
  }

  private async sendPrepared(): Promise<void> {
    const prepared = this.prepared;
    if (!prepared || this.view.ended) return;
    const progress = (fraction: number): void => {
      if (this.prepared === prepared) this.set({ upload: { ...IDLE_UPLOAD, phase: "uploading", progress: fraction } });
    };
    progress(0);
    try {
      const stored = await sendPhoto(this.view.credentials, prepared, prepared.lens, progress);
      if (this.prepared !== prepared) return; // another photo was chosen meanwhile
      this.prepared = null;
      this.before = null;
      this.landed({ width: stored.width, height: stored.height });
    } catch (error) {
      if (this.prepared !== prepared) return;
      if (error instanceof ApiError && error.sessionEnded) {
        this.end("ended");
        return;
      }
      const retryable = isRetryable(error);
      const message = retryable
        ? "The photo could not be sent: no connection. Your taps are kept. Retry when you have a signal."
        : error instanceof Error
          ? error.message
          : String(error);
      this.set({
        upload: { ...IDLE_UPLOAD, phase: "failed", message, retryable },
      });
    }
  }

  /**
   * The server has the new photo (of size `size`) and no taps on it: the taps made on the
   * phone's copy meanwhile go now. The phone keeps showing its own copy: no download.
   */
  private landed(size: { width: number; height: number }): void {
    const shown = this.view.photo;
    const local = shown?.pending ? shown : null;
    this.saver.saved(toServerTaps(fromServerTaps(null)));
    let editor = local ? this.view.editor : newEditor();
    if (local && (local.size.width !== size.width || local.size.height !== size.height)) {
      editor = newEditor(scaleTaps(editor.taps, local.size, size));
    }
    const photo: ShownPhoto = local
      ? { ...local, size, pending: false }
      : { size, key: `${Date.now()}` };
    this.set({
      upload: IDLE_UPLOAD,
      photo,
      editor,
      ...(local ? {} : { unseen: false, mode: startingMode(false, false), linePoint: null }),
    });
    this.saver.hold(false);
    this.saver.update(toServerTaps(editor.taps));
    this.keepDraft();
  }

  // --- taps ----------------------------------------------------------------------------------

  private theirIds(): number[] {
    const state = this.view.state;
    return state ? landmarkIds(fromServerTaps(state.taps[otherRole(this.role)])) : [];
  }

  private edit(editor: TapEditor, patch: Partial<SessionView> = {}): void {
    const changed = editor.taps !== this.view.editor.taps;
    this.set({ editor, ...patch });
    if (changed) {
      this.saver.update(toServerTaps(editor.taps));
      this.keepDraft();
    }
  }

  private keepDraft(): void {
    if (this.view.photo?.pending) return; // taps on a photo the server does not have yet
    saveDraft({
      session_id: this.view.credentials.session_id,
      taps: toServerTaps(this.view.editor.taps),
      unsaved: this.saver.pending,
      skipped: [...this.view.skipped],
      unseen: this.view.unseen,
    });
  }

  setMode(mode: Mode): void {
    this.set({ mode, linePoint: null });
  }

  /** A tap on the photo at `at` (photo pixels, inside the photo): place what the mode says. */
  tap(at: Tap): void {
    const { editor, mode } = this.view;
    switch (mode) {
      case "friend":
        this.edit(setFriend(editor, at, at.sigma), { mode: "landmark", unseen: false });
        return;
      case "line": {
        const first = this.view.linePoint;
        if (!first) {
          this.set({ linePoint: at });
          return;
        }
        const line = Math.hypot(first.x - at.x, first.y - at.y) >= 2 ? lineThrough(first, at) : null;
        if (line) {
          const friendLine = { ...line, sigma: lineSigma(first.sigma, at.sigma) };
          this.edit(setFriendLine(editor, friendLine), { mode: "landmark", linePoint: null });
        } else {
          this.set({ linePoint: at });
        }
        return;
      }
      case "landmark":
        this.edit(addLandmark(select(editor, null), at, at.sigma, this.theirIds(), this.view.skipped));
        return;
    }
  }

  /** Landmark `id` dragged to `to`: it takes the precision of this placement. */
  moveLandmark(id: number, to: Tap): void {
    this.edit(moveLandmark(this.view.editor, id, to, to.sigma));
  }

  select(id: number | null): void {
    this.set({ editor: select(this.view.editor, id) });
  }

  deleteSelected(): void {
    const { selected } = this.view.editor;
    if (selected !== null) this.edit(deleteLandmark(this.view.editor, selected));
  }

  undo(): void {
    const editor = undo(this.view.editor);
    // The friend mark undone: the next tap marks the friend again, unless they are not seen.
    const unmarked = !friendMarked(editor.taps) && friendMarked(this.view.editor.taps) && !this.view.unseen;
    this.edit(editor, { linePoint: null, ...(unmarked ? { mode: "friend" as const } : {}) });
  }

  removeFriend(): void {
    this.edit(setFriend(this.view.editor, null), { mode: "landmark", linePoint: null });
  }

  /** "I can't see them": landmarks only, and this phone is not asked again for this photo. */
  cannotSee(): void {
    this.set({ unseen: true, mode: "landmark", linePoint: null });
    this.keepDraft();
  }

  /** "I can't see #n here": the next prompt asks for another landmark. */
  skip(id: number): void {
    this.set({ skipped: new Set([...this.view.skipped, id]) });
    this.keepDraft();
  }

  retrySave(): void {
    this.saver.retryNow();
  }

  // --- the end -------------------------------------------------------------------------------

  async deleteNow(): Promise<boolean> {
    try {
      await deleteSession(this.view.credentials);
    } catch (error) {
      if (!(error instanceof ApiError && error.sessionEnded)) {
        this.set({ deleteError: error instanceof Error ? error.message : String(error) });
        return false;
      }
    }
    this.end("deleted");
    return true;
  }

  /** Leave this session for a new one: deleted on the server, forgotten here. */
  abandon(): void {
    this.stop();
    forgetSession();
    void deleteSession(this.view.credentials).catch(() => undefined);
  }

  clearDeleteError(): void {
    this.set({ deleteError: null });
  }
}

/** What the first tap on a photo places: the friend, unless marked or said to be unseen. */
function startingMode(marked: boolean, unseen: boolean): Mode {
  return marked || unseen ? "landmark" : "friend";
}
