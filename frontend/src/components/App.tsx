/** The app: which screen the address and the stored session call for. */

import { useEffect, useState } from "preact/hooks";
import { createSession, joinSession } from "../api";
import { t, useLanguage } from "../i18n";
import { errorText } from "../i18n/server";
import { SESSION_PATH, go, parseRoute, type Route } from "../routes";
import { loadCredentials, saveCredentials } from "../storage";
import type { Credentials } from "../types";
import { SessionScreen } from "./SessionScreen";
import { StartScreen } from "./StartScreen";

export function App() {
  // The switch re-renders the whole app in the new language, its state kept.
  useLanguage();
  const [route, setRoute] = useState<Route>(() => parseRoute(location.pathname));
  const [credentials, setCredentials] = useState<Credentials | null>(loadCredentials);
  const [joinError, setJoinError] = useState<{ code: string; message: string } | null>(null);

  useEffect(() => {
    const onPop = (): void => {
      setCredentials(loadCredentials());
      setRoute(parseRoute(location.pathname));
    };
    window.addEventListener("popstate", onPop);
    return () => window.removeEventListener("popstate", onPop);
  }, []);

  const enter = (next: Credentials): void => {
    saveCredentials(next);
    setCredentials(next);
    go(SESSION_PATH, route.name === "join");
    setRoute({ name: "session" });
  };

  const toStart = (): void => {
    setCredentials(loadCredentials());
    go("/");
    setRoute({ name: "start" });
  };

  // The session address without a session (it ended, or storage was cleared): the start.
  useEffect(() => {
    if (route.name === "session" && !credentials) go("/", true);
  }, [route, credentials]);

  // The join link: join at once, then the session screen (a reload there stays in it).
  useEffect(() => {
    if (route.name !== "join") return;
    let active = true;
    joinSession(route.code).then(
      (joined) => {
        if (active) enter({ session_id: joined.session_id, token: joined.token, role: joined.role });
      },
      (error: unknown) => {
        if (!active) return;
        setJoinError({ code: route.code, message: errorText(error) });
        go("/", true);
        setRoute({ name: "start" });
      },
    );
    return () => {
      active = false;
    };
  }, [route]);

  if (route.name === "join") {
    return (
      <main class="screen center">
        <p class="big-note" role="status">
          {t("app.joining")}
        </p>
      </main>
    );
  }
  if (route.name === "session" && credentials) {
    const newSearch = (): void => {
      createSession().then(
        (created) => enter({ session_id: created.session_id, token: created.token, role: created.role }),
        () => toStart(),
      );
    };
    return (
      <SessionScreen
        key={credentials.session_id}
        credentials={credentials}
        onLeave={toStart}
        onNewSearch={newSearch}
      />
    );
  }
  return (
    <StartScreen
      resume={credentials}
      onResume={() => {
        go(SESSION_PATH);
        setRoute({ name: "session" });
      }}
      onEnter={enter}
      initialCode={joinError?.code ?? ""}
      initialError={joinError?.message ?? null}
    />
  );
}
