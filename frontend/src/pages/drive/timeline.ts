// The homing run's live timeline: statusword samples as they arrive, turned into on-segments
// per bit (10 target reached, 12 homing attained, 13 homing error) across a fixed width.

export interface Sample {
  /** ms since the run started */
  t: number;
  statusword: number;
}

export const TIMELINE_BITS = [
  { bit: 10, label: "drive.homing.bit10" },
  { bit: 12, label: "drive.homing.bit12" },
  { bit: 13, label: "drive.homing.bit13" },
] as const;

export const MAX_SAMPLES = 600;

/** Add a sample; a repeat of the last word only moves the end of time (kept small). */
export function addSample(samples: readonly Sample[], sample: Sample): Sample[] {
  const last = samples.at(-1);
  const previous = samples.at(-2);
  if (
    last &&
    previous &&
    last.statusword === sample.statusword &&
    previous.statusword === sample.statusword
  ) {
    return [...samples.slice(0, -1), sample];
  }
  return [...samples, sample].slice(-MAX_SAMPLES);
}

/** [x0, x1] ranges where `bit` is on, with time scaled to `width` over [0, span] ms. */
export function segments(
  samples: readonly Sample[],
  bit: number,
  width: number,
  span: number,
): [number, number][] {
  const out: [number, number][] = [];
  const scale = span > 0 ? width / span : 0;
  samples.forEach((sample, i) => {
    if (((sample.statusword >> bit) & 1) === 0) return;
    const next = samples[i + 1];
    const x0 = sample.t * scale;
    const x1 = (next ? next.t : span) * scale;
    const last = out.at(-1);
    if (last && Math.abs(last[1] - x0) < 1e-9) last[1] = x1;
    else out.push([x0, x1]);
  });
  return out.filter(([a, b]) => b > a);
}
