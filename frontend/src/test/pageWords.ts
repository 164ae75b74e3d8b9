// What a page says in words, for the translated-page tests: its text and the values of its
// aria-label, title and placeholder attributes, one to a line.

const ATTRIBUTES = ["aria-label", "title", "placeholder"];

/** The text of `root` and its elements' aria-label, title and placeholder values, the elements
 * matching any `leaveOut` selector (the server's texts, shared parts) removed first. */
export function pageWords(root: HTMLElement, leaveOut: string[] = []): string {
  const copy = root.cloneNode(true) as HTMLElement;
  for (const selector of leaveOut) {
    copy.querySelectorAll(selector).forEach((e) => {
      e.remove();
    });
  }
  const attributes = [...copy.querySelectorAll(ATTRIBUTES.map((a) => `[${a}]`).join(", "))].flatMap(
    (e) => ATTRIBUTES.map((name) => e.getAttribute(name) ?? ""),
  );
  return [copy.textContent, ...attributes].join("\n");
}
