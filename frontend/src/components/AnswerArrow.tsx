/**
 * An arrow at the view's edge towards an answer out of sight; a tap brings it into view. It
 * sits in the controls' layer beside the photo view, not inside it (PhotoView.tsx says why).
 */

import { t as tr } from "../i18n";
import type { AnswerView } from "../answer";
import { clearArea, clipToPhoto, edgeArrow, type Insets } from "../reframe";
import { toScreen, type Size, type ViewTransform } from "../viewTransform";
import { answerBox } from "./AnswerLayer";
import { ArrowIcon } from "./icons";
import { at } from "./Marks";

/** How far inside the view's clear edge the arrow sits, screen px. */
const ARROW_INSET = 34;

interface Props {
  answer: AnswerView;
  photoSize: Size;
  transform: ViewTransform;
  view: Size;
  insets: Insets;
  onShow: () => void;
}

export function AnswerArrow({ answer, photoSize, transform: t, view, insets, onShow }: Props) {
  const box = answerBox(answer);
  if (!box) return null;
  const target = toScreen(t, clipToPhoto(box, photoSize).centre);
  // Out of the view, not merely under the status (which lets the photo show through).
  const arrow = edgeArrow(target, clearArea(view, { ...insets, top: insets.left }), ARROW_INSET);
  if (!arrow) return null;
  const degrees = (arrow.angle * 180) / Math.PI;
  return (
    <button
      type="button"
      class="answer-arrow"
      data-testid="answer-arrow"
      aria-label={tr("answer.showWhere")}
      style={`${at(arrow.at)};transform:translate(-50%,-50%) rotate(${degrees}deg)`}
      onClick={onShow}
    >
      <ArrowIcon />
    </button>
  );
}
