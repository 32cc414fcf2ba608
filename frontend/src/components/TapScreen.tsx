/**
 * Tapping, full-bleed: the photo takes the screen; the answer's status is overlaid compactly
 * on its top (it lets taps through to the photo but for its own buttons); what to do next
 * and the tools are below it, in reach of the thumb and away from the photo's tappable area.
 * Every word is this phone's own (nextStep.ts): never a count that mixes the two phones.
 */

import type { ComponentChildren } from "preact";
import { useEffect, useLayoutEffect, useRef, useState } from "preact/hooks";
import { answerFocusKey, useFocusOnChange } from "../a11y/focus";
import { PhotoDescription } from "../a11y/PhotoDescription";
import { cropUrl, photoUrl } from "../api";
import { describeAnswer, type AnswerView } from "../answer";
import { SUGGESTED_SIGMA_PX, bandOf, misfitsOf } from "../guidance";
import { answerMotion, motionAccess } from "../camera/motion";
import { askOrientation } from "../live/sensor";
import { t } from "../i18n";
import { canUndo, friendMarked, fromServerTaps, landmarkIds } from "../landmarks";
import { lensNote } from "../lens";
import { nextStep, type Step } from "../nextStep";
import { landmarkColour } from "../palette";
import type { Insets } from "../viewTransform";
import type { Mode, SessionController, SessionView } from "../session";
import { otherRole, type SessionState } from "../types";
import { LineIcon, PersonIcon, PinIcon, TrashIcon, UndoIcon } from "./icons";
import { useSuggestion, type Guide } from "./GuideLayer";
import { PhotoView, type Focus } from "./PhotoView";
import { UploadStatus } from "./PhotoStep";
import { UploadBar, uploadReplacesPrompt } from "./UploadBar";

interface Props {
  controller: SessionController;
  view: SessionView;
  state: SessionState;
  top: ComponentChildren;
}

/** The live view ("Show me"): a chunk of its own, fetched when first opened. */
type LiveViewComponent = typeof import("../live/LiveView").LiveView;

/** Room kept clear at the view's sides and bottom when the answer is brought into view. */
const MARGIN = 12;
/** The controls along the photo's bottom (the whole-photo button, 48 px at 12 px from the
 * edge; the hints and the upload bar are no taller): the answer is brought above them. */
const CONTROLS = 60;

export function TapScreen({ controller, view, state, top }: Props) {
  const { credentials, editor, photo } = view;
  const role = credentials.role;
  const answerState = view.answerState ?? state;
  const answer = describeAnswer(answerState, role);
  const [focus, setFocus] = useState<Focus | null>(null);
  const status = useRef<HTMLElement>(null);
  const stage = useRef<HTMLDivElement>(null);
  const [covered, setCovered] = useState(0);
  // The status opened whole ("More"): over the photo until closed, or until a new answer.
  const [statusOpen, setStatusOpen] = useState(false);
  const [live, setLive] = useState(false);
  const [LiveView, setLiveView] = useState<LiveViewComponent | null>(null);
  // This phone's part of the answer, for "Show me": once there is a point or a curve.
  const mine = answerState.answer?.in_photo[role] ?? null;
  const canShow = Boolean(mine?.drawing) && (answer.position !== null || answer.kind === "curve");
  // The answer the live view shows: the newest with something to show, kept while it is
  // open (a state fetched again, an answer being renewed, must not close it).
  const shown = useRef<{ answer: AnswerView; mine: NonNullable<typeof mine> } | null>(null);
  if (canShow && mine) shown.current = { answer, mine };
  const showMe = (): void => {
    // iOS lets the page read the orientation only when asked from a tap (over HTTPS).
    if (motionAccess() === "ask") void answerMotion(true);
    void askOrientation();
    setLive(true);
    // A chunk that did not come (no signal) closes it again: "Show me" may be tapped anew.
    if (!LiveView)
      import("../live/LiveView").then(
        (module) => setLiveView(() => module.LiveView),
        () => setLive(false),
      );
  };

  const focusOn = (id: number): void => {
    controller.taps.select(id);
    setFocus({ id, nonce: Date.now() });
  };

  // How much of the photo's top the status covers (upright; on its side the phone shows the
  // status beside the photo): an answer is brought into the rest.
  useLayoutEffect(() => {
    const panel = status.current;
    const photoArea = stage.current;
    // Opened whole, the status covers the photo only while it is read: the answer stays.
    if (!panel || !photoArea || statusOpen) return;
    const measure = (): void => {
      const over = panel.getBoundingClientRect();
      const under = photoArea.getBoundingClientRect();
      const overlaps = over.left < under.right && over.right > under.left && over.top < under.bottom;
      setCovered(overlaps ? Math.max(0, over.bottom - under.top) : 0);
    };
    measure();
    const observer = new ResizeObserver(measure);
    observer.observe(panel);
    observer.observe(photoArea);
    return () => observer.disconnect();
  }, [photo !== null, statusOpen]);

  // A keyboard on a desktop: undo, delete, deselect.
  useEffect(() => {
    const onKey = (event: KeyboardEvent): void => {
      if (event.target instanceof HTMLInputElement) return;
      if ((event.ctrlKey || event.metaKey) && event.key.toLowerCase() === "z") {
        event.preventDefault();
        controller.taps.undo();
      } else if (event.key === "Delete" || event.key === "Backspace") {
        controller.taps.deleteSelected();
      } else if (event.key === "Escape") {
        controller.taps.select(null);
      }
    };
    window.addEventListener("keydown", onKey);
    return () => window.removeEventListener("keydown", onKey);
  }, [controller]);

  // Focus follows the next step (a11y/focus.ts): the photo to tap once it is shown, the
  // answer's status once one arrives (later, on its own), which the status then reads out.
  useFocusOnChange(() => stage.current?.querySelector<HTMLElement>('[data-testid="photo-view"]'), photo?.key ?? null);
  const answerKey = answerFocusKey(answer.kind, answer.position?.how ?? null);
  useFocusOnChange(() => status.current, answerKey);
  useEffect(() => setStatusOpen(false), [answerKey]);

  const step = stepOf(state, view, answer);
  // The landmark to find, its band under the answer, and a suggested spot on it.
  const findId = step.next.find ? step.next.id : null;
  const band = findId === null ? null : bandOf(answerState, role, findId);
  const spot = useSuggestion(credentials, band ? findId : null, band ? (answerState.answer_version ?? null) : null);
  const guide: Guide | null = band && findId !== null ? { id: findId, band, spot: spot ?? null } : null;
  const suggestion = !guide ? "no-band" : spot === undefined ? "asking" : spot ? "shown" : "none";
  // Landmarks to re-check: those the fit left out, and those far outside their band.
  const recheck = [...new Set([...answer.suspects, ...misfitsOf(answerState, role)])].sort((a, b) => a - b);

  if (!photo) return null;
  const insets: Insets = { top: covered + MARGIN, right: MARGIN, bottom: CONTROLS + MARGIN, left: MARGIN };

  return (
    <main class="screen session tap-screen">
      <h1 class="visually-hidden">{t("a11y.tapScreenTitle")}</h1>
      {top}
      <div class="stage" ref={stage}>
        <PhotoView
          photoUrl={photo.local ?? photoUrl(credentials, role, photo.key)}
          photoSize={photo.size}
          answer={answer}
          guide={guide}
          insets={insets}
          taps={editor.taps}
          selected={editor.selected}
          suspects={recheck}
          linePoint={view.linePoint}
          keepClear={answer.position ? [answer.position] : []}
          focus={focus}
          onTap={(at) => controller.taps.tap(at)}
          onMove={(id, to) => controller.taps.moveLandmark(id, to)}
          onSelect={(id) => controller.taps.select(id)}
        />
        <PhotoDescription taps={editor.taps} photo={photo.size} selected={editor.selected} suspects={recheck} answer={answer} />
      </div>
      <StatusPanel
        panel={status}
        hint={statusHint(state, view)}
        saveError={view.save.status === "error" ? view.save.message : null}
        answer={answer}
        lens={lensNote(state.photos[role])}
        recheck={recheck}
        onRecheck={focusOn}
        onShowMe={canShow ? showMe : null}
        open={statusOpen}
        onOpen={setStatusOpen}
      />
      <Prompt controller={controller} view={view} state={state} step={step} guide={guide} suggestion={suggestion} />
      <UploadBar view={view} />
      <Toolbar controller={controller} view={view} />
      {live && shown.current && LiveView && (
        <LiveView credentials={credentials} answer={shown.current.answer} mine={shown.current.mine} onClose={() => setLive(false)} />
      )}
    </main>
  );
}

/** This phone's next step, from the state and its own taps. */
function stepOf(state: SessionState, view: SessionView, answer: AnswerView): Step {
  const role = view.credentials.role;
  const other = otherRole(role);
  const theirs = fromServerTaps(state.taps[other]);
  const mine = view.editor.taps;
  return nextStep({
    mine: landmarkIds(mine),
    theirs: landmarkIds(theirs),
    skipped: view.skipped,
    needed: state.landmarks_needed,
    theirPhoto: Boolean(state.photos[other]),
    iMarked: friendMarked(mine),
    theyMarked: friendMarked(theirs),
    toldWhere: answer.news && answer.kind !== "none" && answer.kind !== "refused",
    seen: answer.seen,
  });
}

/** What to do while there is no answer yet; null when the prompt below already says it
 * ("Tap your friend"): words over the photo only where they tell something new. */
function statusHint(state: SessionState, view: SessionView): string | null {
  const other = otherRole(view.credentials.role);
  const theirs = fromServerTaps(state.taps[other]);
  if (!friendMarked(view.editor.taps) && !view.unseen) {
    return friendMarked(theirs)
      ? t("tap.hintTheyMarked")
      : null;
  }
  if (!state.photos[other]) return t("tap.hintTakingPhoto");
  return t("tap.hintSameSpots");
}

interface StatusProps {
  panel: { current: HTMLElement | null };
  hint: string | null;
  saveError: string | null;
  answer: AnswerView;
  /** What the phone says of its photo's lens. */
  lens: string | null;
  /** Landmarks to re-check: left out of the answer, or not fitting the others. */
  recheck: readonly number[];
  onRecheck: (id: number) => void;
  /** Opens the live view that points at the friend ("Show me"); null: nothing to show yet. */
  onShowMe: (() => void) | null;
  /** Whether the status is opened whole, over the photo (its "More"). */
  open: boolean;
  onOpen: (open: boolean) => void;
}

/**
 * The answer's status over the photo's top: the sentence saying what is drawn, how sure it
 * is in words, warnings, and a button per landmark to re-check. Only its buttons take taps;
 * elsewhere taps reach the photo (a sibling, so a touch beside a button stays on the photo:
 * PhotoView.tsx). It keeps to the photo's top part; words that do not fit there (large
 * text, a small screen) are behind a "More" that opens it whole, scrolling if need be,
 * until "Less".
 */
function StatusPanel({ panel, hint, saveError, answer, lens, recheck, onRecheck, onShowMe, open, onOpen }: StatusProps) {
  const { position } = answer;
  const ellipse = position?.ellipse ?? null;
  const body = useRef<HTMLDivElement>(null);
  const content = useRef<HTMLDivElement>(null);
  const [cut, setCut] = useState(false);
  // Whether the words are taller than the room the status has: observed sizes, so a
  // render costs no layout of its own (a tap's frame on a slow phone: docs/slow-phone.md).
  useLayoutEffect(() => {
    const [room, words] = [body.current, content.current];
    if (!room || !words || open) return;
    const measure = (): void => setCut(words.offsetHeight > room.clientHeight + 1);
    measure();
    // "More" coming or going resizes the room: answered in the next frame, not within the
    // observer's own (a resize in its callback is a loop browsers report as an error).
    let frame = 0;
    const observer = new ResizeObserver(() => {
      cancelAnimationFrame(frame);
      frame = requestAnimationFrame(measure);
    });
    observer.observe(room);
    observer.observe(words);
    return () => {
      observer.disconnect();
      cancelAnimationFrame(frame);
    };
  }, [open]);
  // What the status says, in the order shown (keyed: a line that comes or goes leaves the
  // others be). Nothing to say: no scrim over the photo (a class, not CSS's :has(:empty),
  // which WebKit does not renew when words come).
  const words = [
    saveError && (
      <p key="save-error" class="save-error" role="alert">
        {saveError}
      </p>
    ),
    answer.kind === "none" && hint && (
      <p key="hint" class="hint">
        {hint}
      </p>
    ),
    answer.kind === "none" && lens && (
      <p key="lens" class="lens-note" data-testid="lens-note">
        {lens}
      </p>
    ),
    answer.seen && (
      <p key="seen" class="seen-status" data-testid="seen-status">
        {t("tap.seen")}
      </p>
    ),
    answer.text && (
      <p key="text" class={`result-text ${answer.kind}`} data-testid="result-text">
        {answer.text}
      </p>
    ),
    position && (
      <p
        key="position"
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
        {answer.sureness ?? (position.how === "solved" ? "" : t("tap.ownMark"))}
      </p>
    ),
    onShowMe && (
      <div key="show-me" class="status-row">
        <button type="button" class="chip show-me" data-testid="show-me" onClick={onShowMe}>
          {t("tap.showMe")}
        </button>
      </div>
    ),
    recheck.length > 0 && (
      <div key="recheck" class="status-row wrap">
        {recheck.map((id) => (
          <button type="button" class="chip suspect" data-testid="recheck" key={id} onClick={() => onRecheck(id)}>
            {t("tap.recheck", { id })}
          </button>
        ))}
      </div>
    ),
    answer.warnings.length > 0 && (
      <ul key="warnings" class="warnings">
        {answer.warnings.map((warning) => (
          <li data-testid="warning" key={warning}>
            {warning}
          </li>
        ))}
      </ul>
    ),
  ].filter(Boolean);
  return (
    <section
      class={["status", open && "open", words.length === 0 && "silent"].filter(Boolean).join(" ")}
      data-testid="status"
      tabIndex={-1}
      ref={panel}
    >
      {/* The words are read out as they change; "More" turning to "Less" is not news. */}
      <div
        class={cut && !open ? "status-body cut" : "status-body"}
        ref={body}
        id="status-body"
        aria-live="polite"
      >
        <div class="status-words" ref={content}>
          {words}
        </div>
      </div>
      {(cut || open) && (
        <button
          type="button"
          class="chip status-more"
          data-testid="status-more"
          aria-expanded={open}
          aria-controls="status-body"
          onClick={() => onOpen(!open)}
        >
          {open ? t("tap.statusLess") : t("tap.statusMore")}
        </button>
      )}
    </section>
  );
}

interface PromptProps {
  controller: SessionController;
  view: SessionView;
  state: SessionState;
  step: Step;
  guide: Guide | null;
  /** Where the search for a suggested spot is: for the tests (data-suggestion). */
  suggestion: string;
}

/** What this phone does next. Publishes the state's `landmarks_needed` (data-needed) and
 * how many landmarks this phone is asked to tap (data-to-tap), for the tests. */
function Prompt({ controller, view, state, step, guide, suggestion }: PromptProps) {
  const { credentials, editor, mode } = view;
  const other = otherRole(credentials.role);
  const theirTaps = fromServerTaps(state.taps[other]);
  const marked = friendMarked(editor.taps);
  const data = {
    "data-testid": "next-step",
    "data-kind": mode === "landmark" ? step.kind : mode,
    "data-needed": String(state.landmarks_needed),
    "data-to-tap": String(step.toTap),
    // The next step is said as it changes (the next landmark to tap or find): a11y/focus.ts.
    "aria-live": "polite",
  } as const;

  if (uploadReplacesPrompt(view)) {
    // A new photo on its way: its progress (or why it failed) instead of the prompt.
    return (
      <section class="prompt upload" {...data}>
        <UploadStatus controller={controller} view={view} />
      </section>
    );
  }

  if (mode === "friend") {
    return (
      <section class="prompt" {...data}>
        <div class="prompt-text" data-testid="friend-prompt">
          <strong>{marked ? t("tap.moveMark") : t("tap.tapFriend")}</strong>
          <span>{marked ? t("tap.tapWhere") : t("tap.notSure")}</span>
        </div>
        {marked ? (
          <button type="button" class="button secondary small" data-testid="remove-friend" onClick={() => controller.taps.removeFriend()}>
            {t("tap.removeMark")}
          </button>
        ) : (
          <button type="button" class="button secondary small" data-testid="cannot-see" onClick={() => controller.taps.cannotSee()}>
            {t("tap.cantSeeThem")}
          </button>
        )}
      </section>
    );
  }
  if (mode === "line") {
    return (
      <section class="prompt" {...data}>
        <div class="prompt-text" data-testid="line-prompt">
          <strong>{view.linePoint ? t("tap.secondPoint") : t("tap.alongHere")}</strong>
          <span>
            {view.linePoint ? t("tap.tapAnother") : t("tap.tapTwo")}
          </span>
        </div>
        <button type="button" class="button secondary small" onClick={() => controller.taps.setMode(marked || view.unseen ? "landmark" : "friend")}>
          {t("tap.cancel")}
        </button>
      </section>
    );
  }
  const { next } = step;
  const swatch = (
    <span class="swatch" style={`--c:${landmarkColour(next.id)}`} data-testid="next-number">
      #{next.id}
    </span>
  );
  if (next.find) {
    const theirs = theirTaps.landmarks.find((l) => l.id === next.id);
    const key = theirs ? `${theirs.x},${theirs.y}` : "";
    const spot = guide?.id === next.id ? guide.spot : null;
    const offered = spot !== null;
    // A suggested spot: "Use #n?" comes beside "Can't see it", which stays where it was, and
    // the words give way to it (said still: the step is read out), not the photo: the row
    // keeps its height, so nothing a finger may be about to tap moves.
    return (
      <section class={`prompt find${offered ? " offered" : ""}`} {...data}>
        <div class="prompt-main" data-testid="find-prompt" data-id={String(next.id)} data-suggestion={suggestion}>
          <img class="crop" src={cropUrl(credentials, other, next.id, key)} width={64} height={64} alt={t("tap.cropAlt", { id: next.id })} />
          <div class={`prompt-text${offered ? " visually-hidden" : ""}`}>
            <strong data-testid="step-title">{step.title}</strong>
            <span data-testid="step-detail">{step.detail}</span>
          </div>
        </div>
        <div class="prompt-actions">
          {spot ? (
            <button
              type="button"
              class="button primary small"
              data-testid="accept-suggestion"
              onClick={() => controller.taps.tap({ ...spot, sigma: SUGGESTED_SIGMA_PX })}
            >
              {t("tap.useSuggestion", { id: next.id })}
            </button>
          ) : null}
          <button type="button" class="button secondary small" data-testid="skip-landmark" onClick={() => controller.taps.skip(next.id)}>
            {t("tap.cantSeeIt")}
          </button>
        </div>
      </section>
    );
  }
  return (
    <section class={`prompt ${step.kind}`} {...data}>
      <div class="prompt-text">
        <strong data-testid="step-title">{step.title}</strong>
        <span data-testid="step-detail">{step.detail}</span>
      </div>
      {step.kind === "tap" && swatch}
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
  const pick = (next: Mode): void => controller.taps.setMode(next);
  return (
    <nav class="toolbar" aria-label={t("tap.tools")}>
      <ModeButton mode="friend" current={mode} testId="mark-friend" label={t("tap.friend")} icon={<PersonIcon />} onPick={pick} />
      <ModeButton mode="line" current={mode} testId="mark-line" label={t("tap.line")} icon={<LineIcon />} onPick={pick} />
      <ModeButton mode="landmark" current={mode} testId="mark-landmark" label={t("tap.landmarks")} icon={<PinIcon />} onPick={pick} />
      <button type="button" class="tool" data-testid="undo" disabled={!canUndo(editor)} onClick={() => controller.taps.undo()}>
        <UndoIcon />
        <span>{t("tap.undo")}</span>
      </button>
      <button
        type="button"
        class="tool"
        data-testid="delete-landmark"
        disabled={editor.selected === null}
        onClick={() => controller.taps.deleteSelected()}
      >
        <TrashIcon />
        <span>{editor.selected === null ? t("tap.delete") : t("tap.deleteId", { id: editor.selected })}</span>
      </button>
    </nav>
  );
}
