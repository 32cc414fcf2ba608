/** One session on this phone: share the code, take the photo, tap, see the answer. */

import { t } from "../i18n";
import type { JSX } from "preact";
import { useEffect } from "preact/hooks";
import type { Credentials } from "../types";
import { keepAwake } from "../wakeLock";
import { EndedScreen } from "./EndedScreen";
import { PhotoInputs } from "./PhotoInputs";
import { PhotoStep } from "./PhotoStep";
import { SharePanel } from "./SharePanel";
import { TapScreen } from "./TapScreen";
import { TopBar } from "./TopBar";
import { useSession } from "./useController";

interface Props {
  credentials: Credentials;
  onLeave: () => void;
  /** Start over with a new session (the join code ran out). */
  onNewSearch: () => void;
}

export function SessionScreen({ credentials, onLeave, onNewSearch }: Props) {
  const [controller, view] = useSession(credentials);

  // The screen stays on while this phone waits for the other one.
  useEffect(() => (view.ended ? undefined : keepAwake()), [view.ended]);

  if (view.ended) return <EndedScreen ending={view.ended} onStart={onLeave} />;

  const { state } = view;
  if (!state) {
    return (
      <main class="screen center">
        {view.loadError ? (
          <>
            <p class="error" role="alert">
              {view.loadError}
            </p>
            <button type="button" class="button primary" onClick={() => controller.sync.reload()}>
              {t("app.tryAgain")}
            </button>
          </>
        ) : (
          <p class="big-note" role="status">
            {t("app.loading")}
          </p>
        )}
      </main>
    );
  }

  // The friend who started the search shares its code until the other joins.
  const waiting = credentials.role === "starter" && !state.participants.joiner?.joined;
  const top = <TopBar controller={controller} view={view} />;
  let screen: JSX.Element;
  const newSearch = (): void => {
    controller.deletion.abandon();
    onNewSearch();
  };
  if (waiting) {
    screen = <SharePanel controller={controller} view={view} state={state} top={top} onNewSearch={newSearch} />;
  }
  else if (!view.photo) screen = <PhotoStep controller={controller} view={view} top={top} />;
  else screen = <TapScreen controller={controller} view={view} state={state} top={top} />;
  return (
    <>
      <PhotoInputs controller={controller} />
      {screen}
    </>
  );
}
