/**
 * This phone's taps on its photo: the friend, a line through them, landmarks, and their
 * edits (landmarks.ts), each change saved to the server (tapSaver.ts) and kept on the phone
 * until it is (storage.ts: a draft that survives a reload).
 */

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
} from "../landmarks";
import { afterPaint } from "../afterPaint";
import { lineSigma } from "../precision";
import { loadDraft, saveDraft } from "../storage";
import type { SaveState, TapSaver } from "../tapSaver";
import { otherRole, type SessionState } from "../types";
import { startingMode, type Mode, type SessionView, type Tap, type ViewStore } from "./view";

export class TapEditing {
  /** A change waits to be kept on the phone and its "saved" shown until the screen shows
   * it (afterPaint); it is sent at once. */
  private saveQueued = false;

  constructor(
    private readonly store: ViewStore,
    private readonly saver: TapSaver,
  ) {}

  private get view(): SessionView {
    return this.store.view;
  }

  /** The taps to start from on the session's first state: unsaved ones kept on this phone
   * (when its photo is on the server), else the server's. */
  firstLoad(state: SessionState): Partial<SessionView> {
    const role = this.view.credentials.role;
    const server = state.taps[role];
    const draft = loadDraft(this.view.credentials.session_id);
    const mine = state.photos[role];
    this.saver.saved(toServerTaps(fromServerTaps(server)));
    let taps = fromServerTaps(server);
    if (draft?.unsaved && draft.taps && mine) {
      taps = fromServerTaps(draft.taps);
      this.saver.update(toServerTaps(taps));
    }
    const unseen = draft?.unseen ?? false;
    return {
      editor: newEditor(taps),
      skipped: new Set(draft?.skipped ?? []),
      unseen,
      mode: startingMode(friendMarked(taps), unseen),
    };
  }

  /** Keep the taps on the phone (a reload starts from them while they are unsaved). */
  keepDraft(): void {
    if (this.view.photo?.pending) return; // taps on a photo the server does not have yet
    saveDraft({
      session_id: this.view.credentials.session_id,
      taps: toServerTaps(this.view.editor.taps),
      unsaved: this.saver.pending,
      skipped: [...this.view.skipped],
      unseen: this.view.unseen,
    });
  }

  private theirIds(): number[] {
    const state = this.view.state;
    return state ? landmarkIds(fromServerTaps(state.taps[otherRole(this.view.credentials.role)])) : [];
  }

  private edit(editor: TapEditor, patch: Partial<SessionView> = {}): void {
    const changed = editor.taps !== this.view.editor.taps;
    const queued = this.saveQueued;
    if (changed) {
      // Sent first, at once: the answer reaches the other phone one round trip after the
      // tap. The draft and the saver's words wait for the paint (showSaved), the newest taps
      // of that moment.
      this.saveQueued = true;
      this.saver.update(toServerTaps(editor.taps));
    }
    // Not "Saved" while a change waits for the screen: the saver takes it from there.
    const saving = changed ? { save: { status: "saving" as const, message: null } } : {};
    this.store.set({ editor, ...patch, ...saving });
    if (!changed || queued) return;
    afterPaint(() => {
      this.saveQueued = false;
      this.keepDraft();
      this.showSaved(this.saver.status);
    });
  }

  /**
   * The saver's words on screen, unless a change waits for the screen before it is kept on
   * the phone: its "saved" would then come before the draft (and a reload then could lose
   * the change), and its "saving" is already shown. Shown again once the change is kept.
   */
  showSaved(save: SaveState): void {
    if (this.saveQueued) return;
    const shown = this.view.save;
    if (save.status !== shown.status || save.message !== shown.message) this.store.set({ save });
  }

  setMode(mode: Mode): void {
    this.store.set({ mode, linePoint: null });
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
          this.store.set({ linePoint: at });
          return;
        }
        const line = Math.hypot(first.x - at.x, first.y - at.y) >= 2 ? lineThrough(first, at) : null;
        if (line) {
          const friendLine = { ...line, sigma: lineSigma(first.sigma, at.sigma) };
          this.edit(setFriendLine(editor, friendLine), { mode: "landmark", linePoint: null });
        } else {
          this.store.set({ linePoint: at });
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
    this.store.set({ editor: select(this.view.editor, id) });
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
    this.store.set({ unseen: true, mode: "landmark", linePoint: null });
    this.keepDraft();
  }

  /** "I can't see #n here": the next prompt asks for another landmark. */
  skip(id: number): void {
    this.store.set({ skipped: new Set([...this.view.skipped, id]) });
    this.keepDraft();
  }

  retrySave(): void {
    this.saver.retryNow();
  }
}
