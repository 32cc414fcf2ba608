/**
 * One phone in one session, put together from its parts by job (session/): staying in touch
 * with the server (sync.ts), this phone's taps (taps.ts), its photo (photo.ts), deleting
 * (deletion.ts), the answer shown (shownAnswer.ts), all patching one view (view.ts).
 * Components read `view` and call the parts' actions; nothing here draws.
 */

import { putTaps } from "./api";
import { Deletion } from "./session/deletion";
import { PhotoUpload } from "./session/photo";
import { ShownAnswer } from "./session/shownAnswer";
import { SessionSync } from "./session/sync";
import { TapEditing } from "./session/taps";
import { ViewStore, type Ending, type SessionView } from "./session/view";
import { holdsUnsent } from "./shell/busy";
import { forgetSession } from "./storage";
import { TapSaver } from "./tapSaver";
import type { Credentials } from "./types";

export type { Ending, Mode, SessionView, Tap, UploadState } from "./session/view";

export class SessionController {
  readonly sync: SessionSync;
  readonly taps: TapEditing;
  readonly photo: PhotoUpload;
  readonly deletion: Deletion;
  private readonly store: ViewStore;
  private readonly saver: TapSaver;
  private readonly answer: ShownAnswer;

  constructor(credentials: Credentials) {
    const store = new ViewStore(credentials);
    this.store = store;
    // The parts call each other through these arrows: each exists by the time one is called.
    this.saver = new TapSaver({
      send: (taps) => putTaps(credentials, taps),
      onSaved: (state) => {
        this.taps.keepDraft();
        this.sync.applyState(state);
      },
      // Through the tap editing: a tap shows "saving" itself, before the saver has it.
      onStatus: (save) => this.taps.showSaved(save),
      onEnded: () => this.end("ended"),
      onSettled: () => this.sync.releaseHeld(),
    });
    const saver = this.saver;
    this.answer = new ShownAnswer(store);
    this.taps = new TapEditing(store, saver);
    const onEnded = (): void => this.end("ended");
    this.sync = new SessionSync(store, {
      saver,
      answer: this.answer,
      taps: this.taps,
      onEnded,
      onConnectionBack: () => this.connectionBack(),
    });
    this.photo = new PhotoUpload(store, {
      saver,
      answer: this.answer,
      taps: this.taps,
      refetch: () => this.sync.refetch(),
      onEnded,
    });
    this.deletion = new Deletion(store, { end: (ending) => this.end(ending), stop: () => this.stop() });
  }

  private releaseShell: () => void = () => undefined;

  get view(): SessionView {
    return this.store.view;
  }

  subscribe(listener: () => void): () => void {
    return this.store.subscribe(listener);
  }

  start(): void {
    this.sync.start();
    // A photo only this page holds (being prepared, or not sent yet) keeps a new build, or
    // a lazily loaded chunk that failed, from reloading it.
    this.releaseShell = holdsUnsent(
      () => this.view.photo?.pending === true || this.view.upload.phase === "preparing",
    );
  }

  stop(): void {
    this.releaseShell();
    this.photo.stop();
    this.sync.stop();
    this.saver.stop();
    this.answer.stop();
  }

  /** The network may be back: the taps and the photo that wait go at once. */
  private connectionBack(): void {
    this.saver.retryNow();
    this.photo.retryIfWaiting();
  }

  private end(ending: Ending): void {
    if (this.view.ended) return;
    this.stop();
    forgetSession();
    this.store.set({ ended: ending });
  }
}
