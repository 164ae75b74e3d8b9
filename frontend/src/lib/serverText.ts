// The server's texts in the page's language. The API keeps its English `message`; a text the
// page can translate also carries `message_id` and `params` (docs/api.md, "Texts in the user's
// language"), looked up in the `server` catalogue. English, an id the catalogue does not know
// (a newer server) or none at all: the server's own words.
import { currentLanguage, i18n, type MessageKey } from "../i18n";

export interface ServerText {
  message: string;
  message_id?: string | null;
  params?: Record<string, string | number>;
}

export function serverText(text: ServerText): string {
  if (currentLanguage() === "en" || !text.message_id) return text.message;
  const key = `server.${text.message_id}` as MessageKey;
  return i18n.t(key, { ...text.params, defaultValue: text.message });
}
