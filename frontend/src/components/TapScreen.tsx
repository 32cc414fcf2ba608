/**
 * Tapping: the status of the answer on top, the photo in the middle, what to tap next and
 * the tools at the bottom (in reach of the thumb). The heights of the bars are fixed, so
 * the photo never jumps while the answer or a prompt changes.
 */

import type { ComponentChildren } from "preact";
import { useEffect, useState } from "preact/hooks";
import { cropUrl, overlayUrl, photoUrl } from "../api";
import { describeAnswer, neededText, type AnswerView } from "../answer";
import { canUndo, friendMarked, fromServerTaps, landmarkIds, nextLandmark } from "../landmarks";
import { lensNote } from "../lens";
import { landmarkColour } from "../palette";
import type { Mode, SessionController, SessionView } from "../session";
import { otherRole, type SessionState } from "../types";
import { LineIcon, PersonIcon, PinIcon, TrashIcon, UndoIcon, EyeIcon } from "./icons";
import { PhotoView, type Focus } from "./PhotoView";
import { UploadStatus } from "./PhotoStep";

interface Props {
  controller: SessionController;
  view: SessionView;
  state: SessionState;
  top: ComponentChildren;
}

export function TapScreen({ controller, view, state, top }: Props) {
  const { credentials, editor, photo } = view;
  const role = credentials.role;
  const answerState = view.answerState ?? state;
  const answer = describeAnswer(answerState, role);
  // The answer is drawn on the photo when it tells this phone something new (where the
  // friend is found); a phone that marked its friend sees it on request. A choice sticks.
  const [chosen, setChosen] = useState<boolean | null>(null);
  const showAnswer = chosen ?? answer.news;
  const [focus, setFocus] = useState<Focus | null>(null);

  const focusOn = (id: number): void => {
    controller.select(id);
    setFocus({ id, nonce: Date.now() });
  };

  // A keyboard on a desktop: undo, delete, deselect.
  useEffect(() => {
    const onKey = (event: KeyboardEvent): void => {
      if (event.target instanceof HTMLInputElement) return;
      if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === "z") {
        event.preventDefault();
        controller.undo();
      } else if (event.key === "Delete" || event.key === "Backspace") {
        controller.deleteSelected();
      } else if (event.key === "Escape") {
        controller.select(null);
      }
    };
    window.addEventListener("keydown", onKey);
    return () => window.removeEventListener("keydown", onKey);
  }, [controller]);

  if (!photo) return null;
  const version = answerState.answer_version;
  const overlay =
    answer.hasOverlay && showAnswer && typeof version === "number" ? overlayUrl(credentials, role, version) : null;

  return (
    <main class="screen session tap-screen">
      {top}
      <StatusPanel
        hint={statusHint(state, view)}
        saveError={view.save.status === "error" ? view.save.message : null}
        state={state}
        answer={answer}
        lens={lensNote(state.photos[role])}
        showAnswer={showAnswer}
        onToggleAnswer={() => setChosen(!showAnswer)}
        onRecheck={focusOn}
      />
      <PhotoView
        photoUrl={photoUrl(credentials, role, photo.key)}
        photoSize={photo.size}
        overlayUrl={overlay}
        taps={editor.taps}
        selected={editor.selected}
        suspects={answer.suspects}
        linePoint={view.linePoint}
        keepClear={overlay && answer.position ? [answer.position] : []}
        focus={focus}
        onTap={(at) => controller.tap(at)}
        onMove={(id, to) => controller.moveLandmark(id, to)}
        onSelect={(id) => controller.select(id)}
      />
      <Prompt controller={controller} view={view} state={state} />
      <Toolbar controller={controller} view={view} />
    </main>
  );
}

/** What to do while there is no answer yet. */
function statusHint(state: SessionState, view: SessionView): string {
  const other = otherRole(view.credentials.role);
  const theirs = fromServerTaps(state.taps[other]);
  if (!friendMarked(view.editor.taps) && !view.unseen) {
    return friendMarked(theirs)
      ? "Your friend marked you. If you can see them too, mark them: fewer landmarks are needed."
      : "Whoever can see the other marks them: then fewer landmarks are needed.";
  }
  if (!state.photos[other]) return "Your friend is taking their photo.";
  return "Both tap the same spots: #3 here is #3 there.";
}

interface StatusProps {
  hint: string;
  saveError: string | null;
  state: SessionState;
  answer: AnswerView;
  /** What the phone says of its photo's lens. */
  lens: string | null;
  showAnswer: boolean;
  onToggleAnswer: () => void;
  onRecheck: (id: number) => void;
}

function StatusPanel({ hint, saveError, state, answer, lens, showAnswer, onToggleAnswer, onRecheck }: StatusProps) {
  const count = state.landmarks_needed;
  const { position } = answer;
  const ellipse = position?.ellipse ?? null;
  const refined = position !== null && position.how !== "solved";
  return (
    <section class="status" aria-live="polite">
      <div class="status-row">
        <span class={`needed ${count === 0 ? "done" : ""}`} data-testid="landmarks-needed" data-count={String(count)}>
          {neededText(count)}
        </span>
        {answer.hasOverlay && (
          <button type="button" class="chip" onClick={onToggleAnswer} aria-pressed={showAnswer}>
            <EyeIcon /> {showAnswer ? "Hide" : "Answer"}
          </button>
        )}
      </div>
      {saveError && (
        <p class="save-error" role="alert">
          {saveError}
        </p>
      )}
      {answer.kind === "none" && <p class="hint">{hint}</p>}
      {answer.kind === "none" && lens && (
        <p class="lens-note" data-testid="lens-note">
          {lens}
        </p>
      )}
      {answer.seen && (
        <p class="seen-status" data-testid="seen-status">
          Your friend can now see where you are.
        </p>
      )}
      {answer.text && (
        <p class={`result-text ${answer.kind}`} data-testid="result-text">
          {answer.text}
        </p>
      )}
      {(position || answer.suspects.length > 0) && (
        <div class="status-row wrap">
          {position && (
            <p
              class={`result-position quality-${position.quality}`}
              data-testid="result-position"
              data-x={String(position.x)}
              data-y={String(position.y)}
              data-quality={position.quality}
              data-how={position.how}
              {...(ellipse
                ? {
                    "data-axis-a": String(ellipse.axes[0]),
                    "data-axis-b": String(ellipse.axes[1]),
                    "data-angle": String(ellipse.angle_deg),
                  }
                : {})}
            >
              Quality: {position.quality}
              {ellipse
                ? ` \u00b7 \u00b1${Math.round(ellipse.axes[0])} px`
                : refined
                  ? " \u00b7 your mark, refined"
                  : " \u00b7 no sure region"}
            </p>
          )}
          {answer.suspects.map((id) => (
            <button type="button" class="chip suspect" key={id} onClick={() => onRecheck(id)}>
              Re-check #{id}
            </button>
          ))}
        </div>
      )}
      {answer.warnings.length > 0 && (
        <ul class="warnings">
          {answer.warnings.map((warning) => (
            <li data-testid="warning" key={warning}>
              {warning}
            </li>
          ))}
        </ul>
      )}
    </section>
  );
}

function Prompt({ controller, view, state }: { controller: SessionController; view: SessionView; state: SessionState }) {
  const { credentials, editor, mode } = view;
  const other = otherRole(credentials.role);
  const theirTaps = fromServerTaps(state.taps[other]);
  const next = nextLandmark(landmarkIds(editor.taps), landmarkIds(theirTaps), view.skipped);
  const marked = friendMarked(editor.taps);

  if (view.upload.phase !== "idle") {
    // A new photo on its way: its progress (or why it failed) instead of the prompt.
    return (
      <section class="prompt upload">
        <UploadStatus controller={controller} view={view} />
      </section>
    );
  }

  if (mode === "friend") {
    return (
      <section class="prompt" data-testid="friend-prompt">
        <div class="prompt-text">
          <strong>{marked ? "Move your mark?" : "Tap your friend"}</strong>
          <span>{marked ? "Tap where they are." : "Not sure where? Line."}</span>
        </div>
        {marked ? (
          <button type="button" class="button secondary small" data-testid="remove-friend" onClick={() => controller.removeFriend()}>
            Remove mark
          </button>
        ) : (
          <button type="button" class="button secondary small" data-testid="cannot-see" onClick={() => controller.cannotSee()}>
            I can't see them
          </button>
        )}
      </section>
    );
  }
  if (mode === "line") {
    return (
      <section class="prompt" data-testid="line-prompt">
        <div class="prompt-text">
          <strong>{view.linePoint ? "Now a second point" : "Somewhere along here?"}</strong>
          <span>
            {view.linePoint ? "Tap another point on the line." : "Tap 2 points on a line through your friend."}
          </span>
        </div>
        <button type="button" class="button secondary small" onClick={() => controller.setMode(marked || view.unseen ? "landmark" : "friend")}>
          Cancel
        </button>
      </section>
    );
  }
  const swatch = <span class="swatch" style={`--c:${landmarkColour(next.id)}`}>{next.id}</span>;
  if (next.find) {
    const theirs = theirTaps.landmarks.find((l) => l.id === next.id);
    const key = theirs ? `${theirs.x},${theirs.y}` : "";
    return (
      <section class="prompt find" data-testid="find-prompt" data-id={String(next.id)}>
        <img class="crop" src={cropUrl(credentials, other, next.id, key)} width={64} height={64} alt={`Landmark #${next.id} in the other photo`} />
        <div class="prompt-text">
          <strong>
            Find {swatch} here
          </strong>
          <span>Tap the same spot as in your friend's photo.</span>
        </div>
        <button type="button" class="button secondary small" onClick={() => controller.skip(next.id)}>
          Can't see it
        </button>
      </section>
    );
  }
  return (
    <section class="prompt">
      <div class="prompt-text">
        <strong>Tap a landmark {swatch}</strong>
        <span>A spot you both can see: a corner, a sign, a lamp.</span>
      </div>
    </section>
  );
}

function ModeButton(props: { mode: Mode; current: Mode; testId: string; label: string; icon: ComponentChildren; onPick: (mode: Mode) => void }) {
  const active = props.mode === props.current;
  return (
    <button
      type="button"
      class={`tool ${active ? "active" : ""}`}
      data-testid={props.testId}
      aria-pressed={active}
      onClick={() => props.onPick(props.mode)}
    >
      {props.icon}
      <span>{props.label}</span>
    </button>
  );
}

function Toolbar({ controller, view }: { controller: SessionController; view: SessionView }) {
  const { editor, mode } = view;
  const pick = (next: Mode): void => controller.setMode(next);
  return (
    <nav class="toolbar" aria-label="Tools">
      <ModeButton mode="friend" current={mode} testId="mark-friend" label="Friend" icon={<PersonIcon />} onPick={pick} />
      <ModeButton mode="line" current={mode} testId="mark-line" label="Line" icon={<LineIcon />} onPick={pick} />
      <ModeButton mode="landmark" current={mode} testId="mark-landmark" label="Landmarks" icon={<PinIcon />} onPick={pick} />
      <button type="button" class="tool" data-testid="undo" disabled={!canUndo(editor)} onClick={() => controller.undo()}>
        <UndoIcon />
        <span>Undo</span>
      </button>
      <button
        type="button"
        class="tool"
        data-testid="delete-landmark"
        disabled={editor.selected === null}
        onClick={() => controller.deleteSelected()}
      >
        <TrashIcon />
        <span>{editor.selected === null ? "Delete" : `Delete #${editor.selected}`}</span>
      </button>
    </nav>
  );
}
