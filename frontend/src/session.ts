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
  uploadPhoto,
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
import {
  LiveStream,
  Refetcher,
  alreadyShown,
  backoffDelay,
  withRetry,
  type Change,
  type StreamStatus,
} from "./reconnect";
import { forgetSession, loadDraft, saveDraft } from "./storage";
import { TapSaver, type SaveState } from "./tapSaver";
import { otherRole, type Credentials, type LensFields, type SessionState } from "./types";
import type { Point, Size } from "./viewTransform";

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
  /** This phone's stored photo: its size, and a key that changes with each new photo. */
  readonly photo: { size: Size; key: string } | null;
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
      onStatus: (stream) => this.set({ stream }),
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
      if (document.visibilityState === "visible") this.stream.wake();
    };
    const onOnline = (): void => {
      this.stream.wake();
      this.saver.retryNow();
      if (this.view.upload.phase === "failed" && this.view.upload.retryable) void this.retryUpload();
    };
    document.addEventListener("visibilitychange", onVisible);
    window.addEventListener("online", onOnline);
    // Now and then, also without an event: a join code runs out silently, and a proxy may
    // hold events back.
    const poll = setInterval(() => {
      if (document.visibilityState === "visible") this.refetcher.request();
    }, POLL_MS);
    this.cleanups.push(
      () => clearInterval(poll),
      () => document.removeEventListener("visibilitychange", onVisible),
      () => window.removeEventListener("online", onOnline),
    );
  }

  stop(): void {
    this.stream.stop();
    this.saver.stop();
    if (this.holdTimer) clearTimeout(this.holdTimer);
    for (const cleanup of this.cleanups.splice(0)) cleanup();
  }

  /**
   * Something changed (or may have: no `change`): fetch the state, unless what is on screen
   * already shows it. The phone's own change is told by the stream before the reply to its
   * PUT brings it with its answer: such news waits for that reply.
   */
  private changed(...changes: Array<Change | undefined>): void {
    if (changes.length === 0) return;
    if (this.saver.sending && changes.every((change) => change !== undefined)) {
      this.heldChanges.push(...(changes as Change[]));
      return;
    }
    if (changes.some((change) => !alreadyShown(change, this.view.state))) {
      this.refetcher.request();
    }
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
    this.set({ state, loadError: null, ...this.answerPatch(state), ...extra });
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
        this.set({ answerState: this.view.state });
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

  /** The lens is read from the chosen file itself: the shrunk copy keeps no EXIF. */
  async choosePhoto(file: File): Promise<void> {
    this.set({ upload: { ...IDLE_UPLOAD, phase: "preparing" } });
    const [lens, prepared] = await Promise.all([readLens(file), preparePhoto(file, browserDecoder())]);
    this.prepared = { ...prepared, lens };
    await this.sendPhoto();
  }

  /** The person read the refusal: back to what was there. */
  dismissUpload(): void {
    this.prepared = null;
    this.set({ upload: IDLE_UPLOAD });
  }

  async retryUpload(): Promise<void> {
    if (this.prepared) await this.sendPhoto();
  }

  private async sendPhoto(): Promise<void> {
    const prepared = this.prepared;
    if (!prepared || this.view.ended) return;
    const progress = (fraction: number): void =>
      this.set({ upload: { ...IDLE_UPLOAD, phase: "uploading", progress: fraction } });
    progress(0);
    try {
      const send = (lens: LensFields) =>
        withRetry(() => uploadPhoto(this.view.credentials, prepared.body, prepared.name, lens, progress), {
          retries: 3,
          isRetryable,
          delay: (n) => backoffDelay(n, { baseMs: 1500 }),
        });
      const stored = await send(prepared.lens).catch((error: unknown) => {
        // EXIF the server will not take (a lens of 65535 mm, say) must not cost the photo:
        // it goes again without, and the server assumes a phone's camera.
        const lensRefused = error instanceof ApiError && error.status === 422;
        if (lensRefused && Object.keys(prepared.lens).length > 0) return send({});
        throw error;
      });
      this.prepared = null;
      // A new photo: the server cleared this phone's taps, and so does the phone.
      this.saver.saved(toServerTaps(fromServerTaps(null)));
      const editor = newEditor();
      this.set({
        upload: IDLE_UPLOAD,
        photo: { size: { width: stored.width, height: stored.height }, key: `${Date.now()}` },
        editor,
        unseen: false,
        mode: startingMode(false, false),
        linePoint: null,
        save: { status: "saved", message: null },
      });
      this.keepDraft();
      this.refetcher.request();
    } catch (error) {
      if (error instanceof ApiError && error.sessionEnded) {
        this.end("ended");
        return;
      }
      const retryable = isRetryable(error);
      const message = retryable
        ? "The photo could not be sent: no connection. Retry when you have a signal."
        : error instanceof Error
          ? error.message
          : String(error);
      this.set({
        upload: { ...IDLE_UPLOAD, phase: "failed", message, retryable },
      });
    }
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
