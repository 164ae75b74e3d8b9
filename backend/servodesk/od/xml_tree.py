"""A small XML tree with line numbers and namespace-free names, built with expat.

ElementTree keeps no line numbers, which every lint warning needs. Entity declarations are
refused: an uploaded file must not be able to expand itself (billion laughs) or read local files.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from xml.parsers import expat

from servodesk.od.model import OdImportError

MAX_DEPTH = 100  # an XDD nests about ten deep; more is a hostile file
# ~200 bytes each in memory; the largest vendor XDDs hold tens of thousands
MAX_ELEMENTS = 500_000


@dataclass(slots=True)  # slots: one per element of a file of up to megabytes
class Node:
    tag: str  # local name, namespace dropped
    attrib: dict[str, str]  # local attribute names
    line: int
    children: list[Node] = field(default_factory=list)
    text: str = ""

    def find(self, tag: str) -> Node | None:
        return next((c for c in self.children if c.tag == tag), None)

    def findall(self, tag: str) -> list[Node]:
        return [c for c in self.children if c.tag == tag]

    def iter(self, tag: str) -> Iterator[Node]:
        """Depth-first, document order, including self."""
        stack = [self]
        while stack:
            node = stack.pop()
            if node.tag == tag:
                yield node
            stack.extend(reversed(node.children))


def text_child(node: Node | None, tag: str) -> str:
    """Stripped text of the first `tag` child; "" when there is none."""
    child = node.find(tag) if node is not None else None
    return child.text.strip() if child is not None else ""


def _local(name: str) -> str:
    return name.rsplit(" ", 1)[-1]


def parse_xml(data: bytes, filename: str) -> Node:
    parser = expat.ParserCreate(namespace_separator=" ")
    parser.buffer_text = True
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    stack: list[Node] = []
    roots: list[Node] = []
    count = 0

    def start(name: str, attrs: dict[str, str]) -> None:
        nonlocal count
        count += 1
        if len(stack) >= MAX_DEPTH or count > MAX_ELEMENTS:
            what = f"nested deeper than {MAX_DEPTH}" if count <= MAX_ELEMENTS else "too many"
            raise OdImportError(
                f"{filename}: line {parser.CurrentLineNumber}: XML elements {what} "
                f"(at most {MAX_DEPTH} levels and {MAX_ELEMENTS} elements); not an XDD"
            )
        node = Node(
            _local(name), {_local(k): v for k, v in attrs.items()}, parser.CurrentLineNumber
        )
        if stack:
            stack[-1].children.append(node)
        else:
            roots.append(node)
        stack.append(node)

    def end(_name: str) -> None:
        stack.pop()

    def text(data: str) -> None:
        if stack:
            stack[-1].text += data

    def entity_decl(*_args: object) -> None:
        raise OdImportError(f"{filename} declares XML entities; refused for safety")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = text
    parser.EntityDeclHandler = entity_decl
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        raise OdImportError(f"{filename} is not well-formed XML: {exc}") from exc
    except (LookupError, ValueError) as exc:  # encoding="xtf-8", "gbk": expat cannot decode it
        raise OdImportError(
            f"{filename}: line {parser.CurrentLineNumber}: cannot read the XML encoding: {exc}"
        ) from exc
    if not roots:
        raise OdImportError(f"{filename} has no XML root element")
    return roots[0]
