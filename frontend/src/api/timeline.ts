// Short names for the live bus timeline's schemas (generated from the backend's OpenAPI): what
// live/ keeps and the Network page's timeline shows.
import type { components } from "./schema";

type Schemas = components["schemas"];

/** One event of the live bus's timeline. */
export type TimelineEvent = Schemas["TimelineEvent"];
export type TimelinePage = Schemas["EventPage"];
export type EventKind = Schemas["EventKind"];
