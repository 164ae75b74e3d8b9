// The app's URLs, for links from one page to another. A leaf: it imports nothing, so a page or
// the fault banner can link to any page without importing the pages (nav/routes.ts imports
// them all, to build the router, the sidebar and the tab bar).

/** The tab a node's link opens when it names none: the first of nav/routes.ts's NODE_TABS. */
export const FIRST_NODE_TAB = "parameters";

/** A node tab's URL: nodeUrl(1, "faults") → "/nodes/1/faults". */
export function nodeUrl(node: number, tab: string = FIRST_NODE_TAB): string {
  return `/nodes/${node}/${tab}`;
}
