/** What the session's parts share, handed to each by session.ts, which makes them. */

import type { TapSaver } from "../tapSaver";
import type { ShownAnswer } from "./shownAnswer";
import type { TapEditing } from "./taps";

export interface SharedParts {
  /** The one saver of this phone's taps: held while a new photo is on its way. */
  saver: TapSaver;
  answer: ShownAnswer;
  taps: TapEditing;
  /** The server says the session is over (deleted by a phone, or timed out). */
  onEnded: () => void;
}
