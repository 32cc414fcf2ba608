/**
 * Deleting the session: "Delete now" (it ends on both phones), or leaving it for a new one.
 */

import { errorText } from "../i18n/server";
import { ApiError, deleteSession } from "../api";
import { forgetSession } from "../storage";
import type { Ending, ViewStore } from "./view";

export interface DeletionParts {
  /** The session is over on this phone: everything stops, the ended screen shows. */
  end: (ending: Ending) => void;
  /** Everything stops (no ended screen: the phone goes on to a new session). */
  stop: () => void;
}

export class Deletion {
  constructor(
    private readonly store: ViewStore,
    private readonly parts: DeletionParts,
  ) {}

  /** Delete the session on the server; false (and `deleteError` shown) when it was not. */
  async deleteNow(): Promise<boolean> {
    try {
      await deleteSession(this.store.view.credentials);
    } catch (error) {
      if (!(error instanceof ApiError && error.sessionEnded)) {
        this.store.set({ deleteError: errorText(error) });
        return false;
      }
    }
    this.parts.end("deleted");
    return true;
  }

  /** Leave this session for a new one: deleted on the server, forgotten here. */
  abandon(): void {
    this.parts.stop();
    forgetSession();
    void deleteSession(this.store.view.credentials).catch(() => undefined);
  }

  clearDeleteError(): void {
    this.store.set({ deleteError: null });
  }
}
