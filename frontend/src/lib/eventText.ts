// A timeline event's words in the page's language (the server's `message_id` + `params`), an
// EMCY's fault named the way the Faults tab names it.
import type { Fault } from "../api/faults";

import { faultWords } from "./faultText";
import { serverText, type ServerText, type TextParams } from "./serverText";

export interface EventWords extends ServerText {
  kind: string;
  data?: Record<string, unknown>;
}

function carriesFault(data: Record<string, unknown> | undefined): data is Record<string, unknown> {
  return typeof data?.code === "number" && typeof data.name_en === "string";
}

export function eventText(event: EventWords): string {
  const overrides: TextParams = {};
  if (event.kind === "emcy" && carriesFault(event.data)) {
    overrides.fault = faultWords(event.data as unknown as Fault);
  }
  return serverText(event, overrides);
}
