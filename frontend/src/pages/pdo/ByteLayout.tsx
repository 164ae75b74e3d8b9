import type { CSSProperties, ReactNode } from "react";

import { odAddress } from "../../lib/format";
import { MAX_BITS, type Layout, type LayoutBlock } from "./model";

const BYTES = Array.from({ length: MAX_BITS / 8 }, (_, i) => i);

function blockText(block: LayoutBlock): string {
  const address = odAddress(block.index, block.subindex);
  const unit = block.unit ? ` · ${block.unit}` : "";
  return `${block.name ?? address} (${address}, ${block.bits} bit${unit})`;
}

function Block({ block, flagged }: { block: LayoutBlock; flagged: boolean }): ReactNode {
  const span = Math.min(block.bits, MAX_BITS - block.startBit);
  const style: CSSProperties = { gridColumn: `${block.startBit + 1} / span ${span}` };
  const classes = [
    "frame-block",
    `hue-${block.position % 6}`,
    block.known ? "" : "unknown",
    flagged ? "flagged" : "",
    span < 8 ? "narrow" : "",
  ];
  return (
    <div
      className={classes.filter(Boolean).join(" ")}
      style={style}
      title={blockText(block)}
      role="listitem"
      aria-label={blockText(block)}
    >
      <span className="frame-name">
        {block.name ?? (block.known ? "" : odAddress(block.index, block.subindex))}
      </span>
      <span className="frame-meta mono">
        {odAddress(block.index, block.subindex)} · {block.bits} bit
        {block.unit && ` · ${block.unit}`}
      </span>
    </div>
  );
}

/**
 * The 8-byte frame as a bar: byte cells above, each mapped object a block spanning its bits
 * (packed little-endian from bit 0), free bits hatched, objects past 64 bits listed in red.
 */
export function ByteLayout({
  layout,
  label,
  flagged = [],
}: {
  layout: Layout;
  /** Accessible name: "TPDO1 frame". */
  label: string;
  /** Mapping positions a problem names. */
  flagged?: readonly number[];
}): ReactNode {
  const inside = layout.blocks.filter((b) => b.startBit < MAX_BITS);
  const outside = layout.blocks.filter((b) => b.startBit >= MAX_BITS || b.overflow);
  const free = MAX_BITS - Math.min(layout.usedBits, MAX_BITS);
  return (
    <div className="frame" data-testid="byte-layout">
      <div className="frame-grid" aria-hidden="true">
        {BYTES.map((byte) => (
          <div
            key={byte}
            className={`frame-byte${byte * 8 < layout.usedBits ? " used" : ""}`}
            style={{ gridColumn: `${byte * 8 + 1} / span 8` }}
          >
            Byte {byte}
          </div>
        ))}
      </div>
      <div className="frame-grid frame-row" role="list" aria-label={label}>
        {inside.map((block) => (
          <Block key={block.position} block={block} flagged={flagged.includes(block.position)} />
        ))}
        {free > 0 && (
          <div
            className="frame-free"
            style={{ gridColumn: `${MAX_BITS - free + 1} / span ${free}` }}
          >
            {layout.blocks.length === 0 ? "nothing mapped" : free >= 8 ? `${free} bits free` : ""}
          </div>
        )}
      </div>
      <div className="frame-foot muted small">
        <span>
          {layout.usedBits} of {MAX_BITS} bits · {layout.bytes} byte{layout.bytes === 1 ? "" : "s"}{" "}
          sent
        </span>
        {outside.length > 0 && (
          <span className="error-text small" role="alert">
            Does not fit in 8 bytes: {outside.map(blockText).join(", ")}
          </span>
        )}
      </div>
    </div>
  );
}
