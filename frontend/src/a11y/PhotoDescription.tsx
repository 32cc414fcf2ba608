/**
 * The photo's text alternative, for screen readers only: where the answer puts the friend,
 * and every mark on the photo (describe.ts). The photo view points at it
 * (aria-describedby); both parts are polite live regions, so a new mark or a new answer is
 * said once as it appears.
 */

import type { AnswerView } from "../answer";
import type { TapSet } from "../landmarks";
import type { Size } from "../viewTransform";
import { t } from "../i18n";
import { describeAnswerPlace, describeMarks } from "./describe";

/** The id the photo view's aria-describedby names. */
export const PHOTO_DESCRIPTION_ID = "photo-description";

interface Props {
  taps: TapSet;
  photo: Size;
  selected: number | null;
  suspects: readonly number[];
  answer: AnswerView;
}

export function PhotoDescription({ taps, photo, selected, suspects, answer }: Props) {
  const where = describeAnswerPlace(answer, photo);
  const marks = describeMarks(taps, photo, selected, suspects);
  return (
    <div id={PHOTO_DESCRIPTION_ID} class="visually-hidden" data-testid="photo-description">
      <p aria-live="polite" data-testid="answer-where">
        {where ?? ""}
      </p>
      <p>{t("a11y.marksTitle")}</p>
      <ul aria-live="polite" data-testid="mark-descriptions">
        {marks.length === 0 ? <li>{t("a11y.noMarks")}</li> : marks.map(({ key, words }) => <li key={key}>{words}</li>)}
      </ul>
    </div>
  );
}
