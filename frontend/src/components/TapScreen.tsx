/**
 * Tapping: the status of the answer on top, the photo in the middle, what to tap next and
 * the tools at the bottom (in reach of the thumb). The heights of the bars are fixed, so
 * the photo never jumps while the answer or a prompt changes.
 */

import type { ComponentChildren } from "preact";
import { useEffect, useState } from "preact/hooks";
import { cropUrl, overlayUrl, photoUrl } from "../api";
import { describeAnswer, neededText, type AnswerView } from "../answer";
import { canUndo, fromServerTaps, landmarkIds, nextLandmark } from "../landmarks";
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
  const seeker = role === "seeker";
  const answerState = view.answerState ?? state;
  const answer = describeAnswer(answerState, role);
  // The buddy's phone shows the answer on the photo; the seeker's on request.
  const [showAnswer, setShowAnswer] = useState(!seeker);
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
  const overlay =
    answer.hasOverlay && showAnswer && answerState.result_version !== null
      ? overlayUrl(credentials, role, answerState.result_version)
      : null;

  return (
    <main class="screen session tap-screen">
      {top}
      <StatusPanel
        hint={statusHint(state, view)}
        saveError={view.save.status === "error" ? view.save.message : null}
        state={state}
        answer={answer}
        seeker={seeker}
        showAnswer={showAnswer}
        onToggleAnswer={() => setShowAnswer(!showAnswer)}
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
        markName={seeker ? "Buddy" : "Friend"}
        keepClear={!seeker && overlay && answer.position ? [answer.position] : []}
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
  const seeker = view.credentials.role === "seeker";
  const { taps } = view.editor;
  if (seeker && !taps.buddyMark && !taps.buddyLine) {
    return "Mark your buddy first: then 3 landmarks are enough.";
  }
  if (!state.photos[otherRole(view.credentials.role)]) {
    return seeker ? "Your buddy is taking their photo." : "Your friend is taking their photo.";
  }
  return "Both tap the same spots: #3 here is #3 there.";
}

interface StatusProps {
  hint: string;
  saveError: string | null;
  state: SessionState;
  answer: AnswerView;
  seeker: boolean;
  showAnswer: boolean;
  onToggleAnswer: () => void;
  onRecheck: (id: number) => void;
}

function StatusPanel({ hint, saveError, state, answer, seeker, showAnswer, onToggleAnswer, onRecheck }: StatusProps) {
  const count = state.landmarks_needed;
  const { position } = answer;
  const ellipse = position?.ellipse ?? null;
  const located = answer.kind === "position" || answer.kind === "elsewhere";
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
      {seeker && located && (
        <p class="seeker-status" data-testid="seeker-status">
          Your buddy can now see where you are.
        </p>
      )}
      {answer.text && (
        <p class={`result-text ${answer.kind}`} data-testid="result-text">
          {seeker && located ? "Stay where you are and wave." : answer.text}
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
              {...(ellipse
                ? {
                    "data-axis-a": String(ellipse.axes[0]),
                    "data-axis-b": String(ellipse.axes[1]),
                    "data-angle": String(ellipse.angle_deg),
                  }
                : {})}
            >
              Quality: {position.quality}
              {ellipse ? ` \u00b7 \u00b1${Math.round(ellipse.axes[0])} px` : " \u00b7 no sure region"}
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
  const seeker = credentials.role === "seeker";
  const buddyMarked = editor.taps.buddyMark !== null || editor.taps.buddyLine !== null;
  const back = (): void => controller.setMode("landmark");

  if (view.upload.phase !== "idle") {
    // A new photo on its way: its progress (or why it failed) instead of the prompt.
    return (
      <section class="prompt upload">
        <UploadStatus controller={controller} view={view} />
      </section>
    );
  }

  if (mode === "buddy") {
    return (
      <section class="prompt">
        <div class="prompt-text">
          <strong>Where is your buddy?</strong>
          <span>Tap them in your photo.</span>
        </div>
        <button type="button" class="button secondary small" onClick={() => controller.setMode("line")}>
          Not sure? Line
        </button>
      </section>
    );
  }
  if (mode === "line") {
    return (
      <section class="prompt">
        <div class="prompt-text">
          <strong>{view.linePoint ? "Now a second point" : "Somewhere along here?"}</strong>
          <span>
            {view.linePoint ? "Tap another point on the line." : "Tap 2 points on a line through your buddy."}
          </span>
        </div>
        <button type="button" class="button secondary small" onClick={() => controller.setMode(buddyMarked ? "landmark" : "buddy")}>
          Cancel
        </button>
      </section>
    );
  }
  if (mode === "seeker") {
    return (
      <section class="prompt">
        <div class="prompt-text">
          <strong>Can you see your friend?</strong>
          <span>Tap them: then 1 landmark is enough.</span>
        </div>
        {editor.taps.seekerMark ? (
          <button type="button" class="button secondary small" onClick={() => controller.removeSeekerMark()}>
            Remove mark
          </button>
        ) : (
          <button type="button" class="button secondary small" onClick={back}>
            Cancel
          </button>
        )}
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
          <span>Tap the same spot as in {seeker ? "your buddy's" : "your friend's"} photo.</span>
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
  const seeker = view.credentials.role === "seeker";
  const pick = (next: Mode): void => controller.setMode(next);
  return (
    <nav class="toolbar" aria-label="Tools">
      {seeker ? (
        <>
          <ModeButton mode="buddy" current={mode} testId="mark-buddy" label="Buddy" icon={<PersonIcon />} onPick={pick} />
          <ModeButton mode="line" current={mode} testId="mark-line" label="Line" icon={<LineIcon />} onPick={pick} />
        </>
      ) : (
        <ModeButton mode="seeker" current={mode} testId="mark-seeker" label="Friend" icon={<PersonIcon />} onPick={pick} />
      )}
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
