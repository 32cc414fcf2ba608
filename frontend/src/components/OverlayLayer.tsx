/**
 * The server's drawing of the answer over the photo. A new version is loaded out of sight
 * and swapped in once it is complete, so the answer never blinks while it is renewed.
 */

import { useState } from "preact/hooks";

export function OverlayLayer({ url, style }: { url: string; style: string }) {
  const [shown, setShown] = useState<string | null>(null);
  return (
    <>
      {shown && (
        <img class="layer overlay" data-testid="result-overlay" src={shown} style={style} alt="The answer drawn on your photo" draggable={false} />
      )}
      {url !== shown && (
        <img class="layer preload" src={url} style={style} alt="" aria-hidden="true" onLoad={() => setShown(url)} />
      )}
    </>
  );
}
