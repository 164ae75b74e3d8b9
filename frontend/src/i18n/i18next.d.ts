// Typed keys: t("…") with a key the English catalogue lacks fails the typecheck.
import "i18next";

import type { EN } from "./catalogues";

declare module "i18next" {
  interface CustomTypeOptions {
    defaultNS: "translation";
    resources: { translation: typeof EN };
    returnNull: false;
  }
}
