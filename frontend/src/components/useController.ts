import { useEffect, useState } from "preact/hooks";
import { SessionController, type SessionView } from "../session";
import type { Credentials } from "../types";

/** The session's controller for this screen's lifetime, and its current view. */
export function useSession(credentials: Credentials): [SessionController, SessionView] {
  const [controller] = useState(() => new SessionController(credentials));
  const [view, setView] = useState(controller.view);
  useEffect(() => {
    const unsubscribe = controller.subscribe(() => setView(controller.view));
    controller.start();
    return () => {
      unsubscribe();
      controller.stop();
    };
  }, [controller]);
  return [controller, view];
}
