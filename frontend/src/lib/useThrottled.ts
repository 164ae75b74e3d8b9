// A value that follows another at most once per `ms`: the first change after a quiet spell
// comes through at once, a burst of changes gives the newest one `ms` after the last it gave.
// For a request keyed on live data (an EMCY storm must not become a storm of reads).
import { useEffect, useRef, useState } from "react";

export function useThrottled<T>(value: T, ms: number): T {
  const [shown, setShown] = useState(value);
  /** Epoch ms `shown` last changed (0: never, so the first change is not held back). */
  const shownAt = useRef(0);
  useEffect(() => {
    if (Object.is(value, shown)) return undefined;
    const wait = Math.max(0, shownAt.current + ms - Date.now());
    const timer = setTimeout(() => {
      shownAt.current = Date.now();
      setShown(value);
    }, wait);
    return () => clearTimeout(timer);
  }, [value, shown, ms]);
  return shown;
}
