"""Where the elements and attributes of an XML text are, from the parser's own positions: for editing it in place.

==================  ===========================================================================
name                what it is
==================  ===========================================================================
:class:`Element`    one element: its name as a namespace-aware reader sees it (``"uri local"``
                    when it is in a namespace), where its start tag starts and ends, where the
                    element ends, the value span of each attribute, and its children
:func:`elements`    the root :class:`Element` of a text, with its descendants to ``depth``
==================  ===========================================================================

The text is parsed once by expat (the parser under ``xml.etree``), with namespace processing on,
as lxml reads it: ``<dynamics xmlns="urn:x"/>`` is not ``dynamics``. Every position comes from
expat's ``CurrentByteIndex`` at a start or end tag, so the text of a comment, a CDATA section, a
processing instruction or an attribute value is never taken for a tag. A start tag is then
tokenized from that position (its name, then ``name = "value"`` or ``name = 'value'`` pairs with
XML white space between), and the names found must be the ones expat reported, in its order: a
value span is exactly the text between one attribute's quotes, entities and all.

Nothing is fetched or expanded: a DTD (where entities are declared: the billion laughs, external
entities) is refused, as the loader refuses it (:func:`course_dynamics.core.urdf.read_description`),
and so is a reference to an entity nobody declared.

>>> raw = b'<r><!-- <a b="1"/> --><a note=\\'b="2"\\' b = "3"/></r>'
>>> a = elements(raw, "t.xml").children[0]
>>> a.name, raw[slice(*a.attributes["b"])], a.empty
('a', b'3', True)
"""
from __future__ import annotations

import codecs
import re
import xml.parsers.expat
from dataclasses import dataclass, field

from ..base.errors import InputError

SPACE = re.compile(rb"[ \t\r\n]*")
NAME = re.compile(rb"[^ \t\r\n=/>]+")  # expat has checked the names; this only finds where each ends
NAMESPACE_SEPARATOR = " "


@dataclass
class Element:
    """An element of the text; positions are byte offsets into it.

    Parameters
    ----------
    name : str
        ``"local"``, or ``"uri local"`` for an element in a namespace.
    qualified : str
        The name as written: ``"local"`` or ``"prefix:local"``.
    start : int
        The ``<`` of its start tag.
    start_end : int
        Just after its start tag's ``>``.
    empty : bool
        Written as ``<name .../>``.
    attributes : dict
        Name (unprefixed attributes only) → (start, end) of its value, quotes excluded.
    values : dict
        Name (unprefixed attributes only) → its value, as expat reads it.
    end : int, optional
        Just after its end tag (``start_end`` for an empty element); -1 until the end tag is read.
    end_tag : int, optional
        The ``<`` of its end tag (``start_end`` for an empty element); -1 until the end tag is read.
    children : list of Element, optional
        Its child elements, down to the depth asked of :func:`elements`.
    """

    name: str                   # "local", or "uri local" for an element in a namespace
    qualified: str              # as written: "local" or "prefix:local"
    start: int                  # the '<' of its start tag
    start_end: int              # just after its start tag's '>'
    empty: bool                 # <name .../>
    attributes: dict            # name (unprefixed attributes only) → (start, end) of its value, quotes excluded
    values: dict                # name (unprefixed attributes only) → its value, as expat reads it
    end: int = -1               # just after its end tag ('start_end' for an empty element)
    end_tag: int = -1           # the '<' of its end tag ('start_end' for an empty element)
    children: list = field(default_factory=list)

    @property
    def default_namespace(self) -> bool:
        """In a namespace although written without a prefix (namespace-aware and other readers disagree on it)."""
        return NAMESPACE_SEPARATOR in self.name and ":" not in self.qualified


def _start_tag(raw: bytes, start: int, encoding: str, reported: list, where: str):
    """(name as written, attribute value spans, just after '>', empty) of the start tag at ``start``."""
    def fail(why):
        raise InputError(f"{where}: the start tag at byte {start} cannot be read ({why})")

    name = NAME.match(raw, start + 1)
    if name is None:
        fail("no name")
    qualified, i, found = name.group().decode(encoding), name.end(), []
    while True:
        i = SPACE.match(raw, i).end()
        if raw.startswith(b"/>", i) or raw.startswith(b">", i):
            break
        attribute = NAME.match(raw, i)
        if attribute is None:
            fail("an attribute without a name")
        i = SPACE.match(raw, attribute.end()).end()
        if not raw.startswith(b"=", i):
            fail("an attribute without '='")
        i = SPACE.match(raw, i + 1).end()
        quote = raw[i:i + 1]
        close = raw.find(quote, i + 1) if quote in (b'"', b"'") else -1
        if close < 0:
            fail("an attribute value without its quotes")
        found.append((attribute.group().decode(encoding), i + 1, close))
        i = close + 1
    empty = raw.startswith(b"/>", i)
    declared = [(n, s, e) for n, s, e in found if n != "xmlns" and not n.startswith("xmlns:")]
    names = reported[0::2]
    if len(declared) != len(names) or any((":" in n) != (NAMESPACE_SEPARATOR in r) or n.split(":")[-1] !=
                                          r.split(NAMESPACE_SEPARATOR)[-1] for (n, _, _), r in zip(declared, names)):
        fail(f"attributes {[n for n, _, _ in declared]} read, expat reports {names}")
    spans = {n: (s, e) for n, s, e in declared if ":" not in n}
    return qualified, spans, i + (2 if empty else 1), empty


def elements(raw: bytes, where: str, depth: int = 2) -> Element:
    """The root element of ``raw``, with its children, theirs, … down to ``depth`` (the root is depth 0).

    Raises :class:`~course_dynamics.base.errors.InputError` (naming ``where``) for text that is not
    well-formed XML, declares a DTD or refers to an undeclared entity.

    Parameters
    ----------
    raw : bytes
        The XML text.
    where : str
        The name of the text in messages (its file).
    depth : int, optional
        How deep to go: 0 for the root alone, 2 for its children's children.

    Returns
    -------
    Element
        The root element.

    Raises
    ------
    InputError
        If the text is not well-formed XML, declares a DTD or an entity, refers to an undeclared entity,
        has a start tag whose attributes cannot be read, or is in an encoding that cannot be edited in place.
    """
    parser = xml.parsers.expat.ParserCreate(None, NAMESPACE_SEPARATOR)
    parser.ordered_attributes = True
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    stack: list = []           # an Element per open element, None below ``depth``
    found: list = []
    encoding = ["utf-8"]

    def declaration(version, declared, standalone):
        if declared:
            encoding[0] = codecs.lookup(declared).name

    def refuse(*_):
        raise InputError(f"{where}: declares a DTD or an entity (<!DOCTYPE ...>); URDF files have none")

    def skipped(name, is_parameter):
        raise InputError(f"{where}: refers to the entity '&{name};', which is not declared")

    def start(name, attributes):
        if len(stack) > depth:
            stack.append(None)
            return
        at = parser.CurrentByteIndex
        qualified, spans, start_end, empty = _start_tag(raw, at, encoding[0], attributes, where)
        values = {n: v for n, v in zip(attributes[0::2], attributes[1::2]) if NAMESPACE_SEPARATOR not in n}
        element = Element(name, qualified, at, start_end, empty, spans, values, *(2 * [start_end if empty else -1]))
        (stack[-1].children if stack else found).append(element)
        stack.append(element)

    def finish(name):
        element = stack.pop()
        if element is not None and not element.empty:
            element.end_tag = parser.CurrentByteIndex
            element.end = raw.index(b">", element.end_tag) + 1

    parser.XmlDeclHandler, parser.StartElementHandler, parser.EndElementHandler = declaration, start, finish
    parser.StartDoctypeDeclHandler = parser.EntityDeclHandler = parser.ExternalEntityRefHandler = refuse
    parser.SkippedEntityHandler = skipped
    try:
        parser.Parse(raw, True)
    except xml.parsers.expat.ExpatError as exc:
        raise InputError(f"{where}: malformed XML: {exc}") from None
    except (LookupError, ValueError) as exc:      # an encoding expat or Python does not know, or multi-byte
        if isinstance(exc, InputError):
            raise
        raise InputError(f"{where}: its encoding cannot be edited in place ({exc}); save it as UTF-8") from None
    return found[0]


__all__ = ["Element", "elements"]
