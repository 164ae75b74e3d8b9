import { useId, type CSSProperties, type ReactNode } from "react";

import { i18n, useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { MAX_BITS, type Layout, type LayoutBlock } from "./model";

const BYTES = Array.from({ length: MAX_BITS / 8 }, (_, i) => i);

function blockText(block: LayoutBlock): string {
  const address = odAddress(block.index, block.subindex);
  const unit = block.unit ? ` · ${block.unit}` : "";
  return i18n.t("pdo.frame.block", {
    name: block.name ?? address,
    address,
    bits: block.bits,
    unit,
  });
}

function Block({
  block,
  flagged,
  describedBy,
}: {
  block: LayoutBlock;
  flagged: boolean;
  describedBy?: string | undefined;
}): ReactNode {
  const { t } = useTranslation();
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
      aria-describedby={describedBy}
    >
      <span className="frame-name">
        {block.name ?? (block.known ? "" : odAddress(block.index, block.subindex))}
      </span>
      <span className="frame-meta mono">
        {odAddress(block.index, block.subindex)} · {t("pdo.frame.bits", { bits: block.bits })}
        {block.unit && ` · ${block.unit}`}
      </span>
    </div>
  );
}

/** Where a problem's note sits under its block: from the block's start rightwards, or (for a
 * block in the frame's second half) ending under the block's end, so it has room to read. */
function noteColumn(block: LayoutBlock): string {
  const end = Math.min(block.startBit + block.bits, MAX_BITS);
  return block.startBit < MAX_BITS / 2 ? `${block.startBit + 1} / -1` : `1 / ${end + 1}`;
}

/**
 * The 8-byte frame as a bar: byte cells above, each mapped object a block spanning its bits
 * (packed little-endian from bit 0), free bits hatched, objects past 64 bits listed in red.
 * An object a problem names is outlined, with the problem written under it.
 */
export function ByteLayout({
  layout,
  label,
  problems,
}: {
  layout: Layout;
  /** Accessible name: "TPDO1 frame". */
  label: string;
  /** Problem messages by mapping position. */
  problems?: ReadonlyMap<number, readonly string[]>;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const inside = layout.blocks.filter((b) => b.startBit < MAX_BITS);
  const outside = layout.blocks.filter((b) => b.startBit >= MAX_BITS || b.overflow);
  const free = MAX_BITS - Math.min(layout.usedBits, MAX_BITS);
  const noted = inside.filter((b) => (problems?.get(b.position)?.length ?? 0) > 0);
  const noteId = (block: LayoutBlock): string => `${id}-p${block.position}`;
  return (
    <div className="frame" data-testid="byte-layout">
      <div className="frame-grid" aria-hidden="true">
        {BYTES.map((byte) => (
          <div
            key={byte}
            className={`frame-byte${byte * 8 < layout.usedBits ? " used" : ""}`}
            style={{ gridColumn: `${byte * 8 + 1} / span 8` }}
          >
            {t("pdo.frame.byte", { byte })}
          </div>
        ))}
      </div>
      <div className="frame-grid frame-row" role="list" aria-label={label}>
        {inside.map((block) => {
          const flagged = noted.includes(block);
          return (
            <Block
              key={block.position}
              block={block}
              flagged={flagged}
              describedBy={flagged ? noteId(block) : undefined}
            />
          );
        })}
        {free > 0 && (
          <div
            className="frame-free"
            style={{ gridColumn: `${MAX_BITS - free + 1} / span ${free}` }}
          >
            {layout.blocks.length === 0
              ? t("pdo.frame.nothingMapped")
              : free >= 8
                ? t("pdo.frame.bitsFree", { free })
                : ""}
          </div>
        )}
      </div>
      {noted.length > 0 && (
        <div className="frame-grid frame-notes">
          {noted.map((block) => (
            <p
              key={block.position}
              id={noteId(block)}
              className={`frame-note error-text${block.startBit < MAX_BITS / 2 ? "" : " end"}`}
              style={{ gridColumn: noteColumn(block) }}
            >
              {problems?.get(block.position)?.join(" ")}
            </p>
          ))}
        </div>
      )}
      <div className="frame-foot muted small">
        <span>
          {t("pdo.frame.used", { used: layout.usedBits, max: MAX_BITS, count: layout.bytes })}
        </span>
        {outside.length > 0 && (
          <span className="error-text small" role="alert">
            {t("pdo.frame.doesNotFit", {
              objects: outside.map(blockText).join(t("common.listSeparator")),
            })}
          </span>
        )}
      </div>
    </div>
  );
}
