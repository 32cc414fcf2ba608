/**
 * What the screen shows of one phone in its session (`SessionView`), and the one place it
 * changes (`ViewStore`): every part of the session (sync.ts, taps.ts, photo.ts, deletion.ts)
 * patches it, components read it and re-render on each patch.
 */

import type { SaveState } from "../tapSaver";
import type { StreamStatus } from "../reconnect";
import { newEditor, type TapEditor } from "../landmarks";
import type { Credentials, SessionState } from "../types";
import type { ShownPhoto } from "../upload";
import type { Point } from "../viewTransform";

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
  /** `state` is the phone's kept copy, not yet confirmed by the server: it is offline. */
  readonly kept: boolean;
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

export const IDLE_UPLOAD: UploadState = { phase: "idle", progress: 0, message: null, retryable: false };

/** What the first tap on a photo places: the friend, unless marked or said to be unseen. */
export function startingMode(marked: boolean, unseen: boolean): Mode {
  return marked || unseen ? "landmark" : "friend";
}

/** The view, and who is told when it changes (a component's re-render: useController.ts). */
export class ViewStore {
  view: SessionView;
  private readonly listeners = new Set<() => void>();

  constructor(credentials: Credentials) {
    this.view = {
      credentials,
      state: null,
      kept: false,
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
  }

  subscribe(listener: () => void): () => void {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  set(patch: Partial<SessionView>): void {
    this.view = { ...this.view, ...patch };
    for (const listener of this.listeners) listener();
  }
}
