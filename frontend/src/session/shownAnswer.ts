/**
 * Which answer the screen shows: the latest, held a moment while a renewed one is computed
 * (it would blink away after each tap otherwise), and none on a new photo still on its way.
 */

import type { SessionState } from "../types";
import type { SessionView, ViewStore } from "./view";

/** How long an answer stays on screen while the next one is being computed, ms. */
const ANSWER_HOLD_MS = 2500;

/** The state to draw the answer from: none while a new photo is on its way (the answer of
 * the photo it replaces does not belong on it). */
function forScreen(view: SessionView, state: SessionState): SessionState {
  return view.photo?.pending ? { ...state, answer: null, answer_error: null } : state;
}

export class ShownAnswer {
  private holdTimer: ReturnType<typeof setTimeout> | null = null;

  constructor(private readonly store: ViewStore) {}

  /** The patch that shows `state`'s answer, or none while a missing answer is held. */
  patchFor(received: SessionState): Partial<SessionView> {
    const state = forScreen(this.store.view, received);
    const hasAnswer = !!state.answer || !!state.answer_error;
    const shown = this.store.view.answerState;
    if (hasAnswer || !shown || (!shown.answer && !shown.answer_error)) {
      this.stop();
      return { answerState: state };
    }
    if (!this.holdTimer) {
      this.holdTimer = setTimeout(() => {
        this.holdTimer = null;
        this.showNow();
      }, ANSWER_HOLD_MS);
    }
    return {};
  }

  /** The current state's answer at once, nothing held (a new photo replaced the old). */
  showNow(): void {
    this.stop();
    const { state } = this.store.view;
    this.store.set({ answerState: state && forScreen(this.store.view, state) });
  }

  stop(): void {
    if (this.holdTimer) clearTimeout(this.holdTimer);
    this.holdTimer = null;
  }
}
