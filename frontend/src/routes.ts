/** The app's addresses: / (start), /join/<code> (the join link), /s (the session). */

import { CODE_DIGITS } from "./limits";

export type Route = { name: "start" } | { name: "join"; code: string } | { name: "session" };

export const SESSION_PATH = "/s";

export function parseRoute(pathname: string): Route {
  const join = new RegExp(`^/join/(\\d{${CODE_DIGITS}})/?$`).exec(pathname);
  if (join?.[1]) return { name: "join", code: join[1] };
  if (pathname === SESSION_PATH || pathname === SESSION_PATH + "/") return { name: "session" };
  return { name: "start" };
}

export function go(path: string, replace = false): void {
  if (location.pathname === path) return;
  if (replace) history.replaceState(null, "", path);
  else history.pushState(null, "", path);
}
