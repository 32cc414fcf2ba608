/**
 * This phone's photo: chosen, shrunk, shown at once and sent behind the person's back
 * (upload.ts), retried, or refused (then back to what was there). Taps made on the phone's
 * copy meanwhile wait (the tap saver holds) and go when the server has the photo.
 */

import { t } from "../i18n";
import { errorText } from "../i18n/server";
import { ApiError, isRetryable } from "../api";
import { browserDecoder, preparePhoto, type PreparedPhoto } from "../downscale";
import { fromServerTaps, newEditor, toServerTaps } from "../landmarks";
import { readLens } from "../lens";
import { saveDraft, saveShutterAnchor } from "../storage";
import type { LensFields, SensorFields } from "../types";
import { localPhoto, scaleTaps, sendPhoto, type ShownPhoto } from "../upload";
import type { SharedParts } from "./parts";
import { IDLE_UPLOAD, startingMode, type SessionView, type ViewStore } from "./view";

export interface PhotoParts extends SharedParts {
  /** Fetch the server's state (the photo it has, after a refused one). */
  refetch: () => void;
}

export class PhotoUpload {
  private prepared: (PreparedPhoto & { lens: LensFields; sensors: SensorFields | null }) | null = null;
  /** What was on screen before a new photo was shown: back to it if that photo is refused. */
  private before: Pick<SessionView, "photo" | "editor" | "unseen" | "mode"> | null = null;

  constructor(
    private readonly store: ViewStore,
    private readonly parts: PhotoParts,
  ) {}

  private get view(): SessionView {
    return this.store.view;
  }

  /**
   * The lens is read from the chosen file itself: the shrunk copy keeps no EXIF. The shrunk
   * copy is shown and tapped on at once; the upload runs behind it (upload.ts). `sensors`:
   * what the in-app camera read at the shutter (none for the phone's camera app or the
   * gallery); `anchor`: its orientation then, kept on the phone for "Show me" (live/).
   */
  async choose(file: File, sensors: SensorFields | null = null, anchor: readonly (readonly number[])[] | null = null): Promise<void> {
    saveShutterAnchor(this.view.credentials.session_id, anchor);
    this.store.set({ upload: { ...IDLE_UPLOAD, phase: "preparing" } });
    const [lens, prepared] = await Promise.all([readLens(file), preparePhoto(file, browserDecoder())]);
    if (this.view.ended) return;
    this.prepared = { ...prepared, lens, sensors };
    const shown = localPhoto(prepared, `local-${Date.now()}`);
    if (shown) this.showNew(shown);
    await this.send();
  }

  /** The person read the refusal: back to what was there. */
  dismiss(): void {
    this.prepared = null;
    const shown = this.view.photo;
    if (shown?.pending) {
      forgetLocal(shown);
      // The photo back on screen is not the one the anchor was read for.
      saveShutterAnchor(this.view.credentials.session_id, null);
      const before = this.before ?? { photo: null, editor: newEditor(), unseen: false, mode: startingMode(false, false) };
      this.before = null;
      this.parts.saver.saved(toServerTaps(before.editor.taps));
      this.parts.saver.hold(false);
      this.store.set({ ...before, linePoint: null, upload: IDLE_UPLOAD, save: { status: "saved", message: null } });
      this.parts.taps.keepDraft();
      this.parts.refetch();
      return;
    }
    this.store.set({ upload: IDLE_UPLOAD });
  }

  async retry(): Promise<void> {
    if (this.prepared) await this.send();
  }

  /** The network may be back: a photo that failed for want of it goes again at once. */
  retryIfWaiting(): void {
    if (this.view.upload.phase === "failed" && this.view.upload.retryable) void this.retry();
  }

  /** The phone's own copy is let go (its object URL). */
  stop(): void {
    forgetLocal(this.view.photo);
  }

  /** A new photo on screen before the server has it: new taps, held until it lands. */
  private showNew(photo: ShownPhoto): void {
    const { editor, unseen, mode } = this.view;
    if (!this.view.photo?.pending) this.before = { photo: this.view.photo, editor, unseen, mode };
    else forgetLocal(this.view.photo);
    this.parts.saver.hold(true);
    this.store.set({
      photo,
      editor: newEditor(),
      unseen: false,
      mode: startingMode(false, false),
      linePoint: null,
    });
    // The answer of the photo it replaces goes at once (not held as a renewed answer is).
    this.parts.answer.showNow();
    // A reload meanwhile starts from the server's photo: nothing of this one is kept.
    saveDraft({ session_id: this.view.credentials.session_id, taps: null, unsaved: false, skipped: [...this.view.skipped], unseen: false });
  }

  private async send(): Promise<void> {
    const prepared = this.prepared;
    if (!prepared || this.view.ended) return;
    const progress = (fraction: number): void => {
      if (this.prepared === prepared) this.store.set({ upload: { ...IDLE_UPLOAD, phase: "uploading", progress: fraction } });
    };
    progress(0);
    try {
      const stored = await sendPhoto(this.view.credentials, prepared, prepared.lens, prepared.sensors, progress);
      if (this.prepared !== prepared) return; // another photo was chosen meanwhile
      this.prepared = null;
      this.before = null;
      this.landed({ width: stored.width, height: stored.height });
    } catch (error) {
      if (this.prepared !== prepared) return;
      if (error instanceof ApiError && error.sessionEnded) {
        this.parts.onEnded();
        return;
      }
      const retryable = isRetryable(error);
      const message = retryable
        ? t("photo.notSent")
        : errorText(error);
      this.store.set({
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
    this.parts.saver.saved(toServerTaps(fromServerTaps(null)));
    let editor = local ? this.view.editor : newEditor();
    if (local && (local.size.width !== size.width || local.size.height !== size.height)) {
      editor = newEditor(scaleTaps(editor.taps, local.size, size));
    }
    const photo: ShownPhoto = local
      ? { ...local, size, pending: false }
      : { size, key: `${Date.now()}` };
    this.store.set({
      upload: IDLE_UPLOAD,
      photo,
      editor,
      ...(local ? {} : { unseen: false, mode: startingMode(false, false), linePoint: null }),
    });
    this.parts.saver.hold(false);
    this.parts.saver.update(toServerTaps(editor.taps));
    this.parts.taps.keepDraft();
  }
}

function forgetLocal(photo: ShownPhoto | null): void {
  if (photo?.local) URL.revokeObjectURL(photo.local);
}
