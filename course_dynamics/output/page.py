"""Every HTML page we write, from one template and one stylesheet, with the mathematics as MathML.

The published notebooks and their index, each student's feedback and the class
summary, the torques page, the offline meshcat animation and the comparison
report are all made by :func:`page`; the helpers below build the pieces of a
body. Nothing here fetches anything: the stylesheet is inlined, scripts are
inlined, and LaTeX becomes MathML when the page is built, so every page opens
from disk with no network (no MathJax, no CDN).

===================  ==============================================================
function             makes
===================  ==============================================================
``page``             a whole page: ``<head>`` with :data:`STYLESHEET`, the body,
                     inline scripts (jinja2, autoescape on)
``fragment``         pieces joined into one piece of HTML (text escaped)
``element``          one element with escaped attributes around its content
``heading``,         ``<h1>``…, ``<p>``, ``<ul>``/``<ol>``, ``<section>``
``paragraph``,
``bullet_list``,
``section``
``table``            rows of cells (class ``numbers`` right-aligns the numbers)
``pre``, ``code``    preformatted text, inline code
``link``             ``<a href>`` to a page beside this one (no ``javascript:``)
``figure``,          a figure with its caption; an SVG we drew; an image as a
``svg``, ``image``   ``data:`` URI
``math``             LaTeX as MathML (:data:`MATHML_TAGS` only, attributes checked)
``markdown``         Markdown as Jupyter reads it (nbconvert's parser), maths as MathML
===================  ==============================================================

Escaping: a ``str`` is text and is always escaped; only ``markupsafe.Markup``
passes as HTML, and only these helpers (and a caller that built HTML on purpose,
such as a matplotlib SVG or the meshcat viewer's script) make it. LaTeX that
latex2mathml cannot convert is shown as escaped code (class ``math-error``) and
the page is still built.

>>> paragraph("x < y for ", math("x^2"))
Markup('<p>x &lt; y for <math display="inline"><mrow><msup><mi>x</mi><mn>2</mn></msup></mrow></math></p>')
>>> math(r"\\frac{1}{")
Markup('<code class="math-error" title="not converted to MathML (NoAvailableTokensError)">$\\\\frac{1}{$</code>')
"""
from __future__ import annotations

import base64
import functools
import html
import re
from collections.abc import Iterable

from markupsafe import Markup

#: The one stylesheet, inlined into every page's ``<head>``.
STYLESHEET = """\
body{font-family:system-ui,sans-serif;max-width:64rem;margin:2rem auto;padding:0 1rem;line-height:1.45;color:#1b1b1b}
h1,h2,h3{line-height:1.2}
table{border-collapse:collapse;margin:.5rem 0}
td,th{border:1px solid #ccc;padding:.25rem .6rem;text-align:left;vertical-align:top}
table.numbers td,table.numbers th{text-align:right}
table.numbers td:first-child,table.numbers th:first-child{text-align:left}
pre{background:#f4f4f4;padding:.6rem;overflow:auto;white-space:pre-wrap}
code,pre{font-family:ui-monospace,SFMono-Regular,Menlo,monospace;font-size:.92em}
pre.input{border-left:3px solid #4a6fa5}
pre.stderr,pre.error{background:#fdecea}
.output{margin:.3rem 0 1rem}
figure{margin:1rem 0}
figure svg{max-width:100%;height:auto}
img,iframe{max-width:100%}
math{font-family:"STIX Two Math","Latin Modern Math","Cambria Math",math}
math[display="block"]{margin:.6rem 0;overflow-x:auto;overflow-y:hidden}
.math-error{color:#b3261e}
.ok{color:#1a7f37}
mark{background:#fff1a8}
table.side-by-side{table-layout:fixed;width:100%}
table.side-by-side td{width:50%}
.bad{color:#b3261e}
body.viewer{margin:0;padding:0;max-width:none}
#meshcat-pane{width:100vw;height:100vh;overflow:hidden}
"""

PAGE_TEMPLATE = """\
<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="course-dynamics">
<title>{{ title }}</title>
<style>
{{ stylesheet }}</style>
{%- if head_extra %}
{{ head_extra }}
{%- endif %}
</head>
<body{% if body_class %} class="{{ body_class }}"{% endif %}>
{{ body }}
{%- for script in scripts %}
<script>{{ script }}</script>
{%- endfor %}
</body>
</html>
"""

NAME = re.compile(r"[a-z][a-z0-9-]*")  # an element's or attribute's name we write
SCHEME = re.compile(r"\s*([a-zA-Z][a-zA-Z0-9+.-]*):")


@functools.cache
def _template():
    import jinja2

    environment = jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined, keep_trailing_newline=True)
    return environment.from_string(PAGE_TEMPLATE)


def page(title, body, *, head_extra: Markup | None = None, scripts: Iterable[str] = (),
         body_class: str | None = None) -> str:
    """One whole HTML page: ``title`` (text), ``body`` (text, Markup or a list of them), the one stylesheet.

    ``scripts`` are inlined, in order, at the end of the body (ours only: the meshcat viewer); a
    ``</script`` inside one is written as ``<\\/script``, which JavaScript reads the same. ``head_extra``
    must be Markup (an element of ours for the ``<head>``); ``body_class`` is a class of :data:`STYLESHEET`
    (``viewer``: the whole window, no margins).

    Parameters
    ----------
    title : str
        The page's title (escaped).
    body : str or markupsafe.Markup or list
        The body: text (escaped), Markup, or a list of them (see :func:`fragment`).
    head_extra : markupsafe.Markup, optional
        An element of ours for the ``<head>``.
    scripts : iterable of str, optional
        JavaScript of ours, each inlined as one ``<script>`` at the end of the body.
    body_class : str, optional
        A class of :data:`STYLESHEET` for the ``<body>``.

    Returns
    -------
    str
        The whole HTML document.

    Raises
    ------
    TypeError
        If ``head_extra`` is text rather than Markup.

    Examples
    --------
    >>> text = page("a <b> & c", "x < y")
    >>> "<title>a &lt;b&gt; &amp; c</title>" in text and "<body>\\nx &lt; y\\n</body>" in text
    True
    """
    if head_extra is not None and not isinstance(head_extra, Markup):
        raise TypeError("head_extra must be Markup built on purpose, not text")
    inline = [Markup(re.sub(r"</(script)", r"<\\/\1", script, flags=re.IGNORECASE)) for script in scripts]
    return _template().render(title=str(title), body=fragment(body), stylesheet=Markup(STYLESHEET),
                              head_extra=head_extra, scripts=inline, body_class=body_class)


# ---------------------------------------------------------------------------- pieces of a body


def fragment(*parts) -> Markup:
    """The parts as one piece of HTML, one line each: a ``str`` is escaped, Markup kept, lists flattened,
    None dropped.

    Parameters
    ----------
    *parts : str or markupsafe.Markup or iterable or None
        The pieces; anything else is escaped as its string.

    Returns
    -------
    markupsafe.Markup
        The pieces joined by line breaks.

    Examples
    --------
    >>> fragment("a < b", None, [element("b", "c")])
    Markup('a &lt; b\\n<b>c</b>')
    """
    pieces = []
    for part in parts:
        if part is None:
            continue
        if isinstance(part, Markup):
            pieces.append(part)
        elif isinstance(part, str):
            pieces.append(html.escape(part, quote=False))
        elif isinstance(part, Iterable) and not isinstance(part, (bytes, bytearray)):
            pieces.append(fragment(*part))
        else:
            pieces.append(html.escape(str(part), quote=False))
    return Markup("\n".join(pieces))


def element(tag: str, *content, inline: bool = False, **attributes) -> Markup:
    """``<tag attributes>content</tag>``; attribute values are escaped, ``class_`` is ``class``, None leaves one out.

    The content's parts are joined by line breaks, or with ``inline`` by nothing.

    Parameters
    ----------
    tag : str
        The element's name (lower case letters, digits and ``-``).
    *content : str or markupsafe.Markup or iterable or None
        The content, as for :func:`fragment`.
    inline : bool, optional
        Join the parts with nothing rather than line breaks.
    **attributes : object
        The attributes (``class_`` for ``class``, ``_`` in a name for ``-``); a value of None leaves one out.

    Returns
    -------
    markupsafe.Markup
        The element.

    Raises
    ------
    ValueError
        If ``tag`` or an attribute's name is not a name we write (an ``on…`` event handler included).

    Examples
    --------
    >>> element("td", "<b>", class_='x" onclick="y')
    Markup('<td class="x&quot; onclick=&quot;y">&lt;b&gt;</td>')
    """
    if not NAME.fullmatch(tag):
        raise ValueError(f"not an element name: {tag!r}")
    written = []
    for name, value in attributes.items():
        name = name.rstrip("_").replace("_", "-")
        if not NAME.fullmatch(name) or name.startswith("on"):
            raise ValueError(f"not an attribute we write: {name!r}")
        if value is not None:
            written.append(f' {name}="{html.escape(str(value), quote=True)}"')
    inner = Markup("").join(fragment(part) for part in content) if inline else fragment(*content)
    return Markup(f"<{tag}{''.join(written)}>{inner}</{tag}>")


def heading(text, level: int = 1, css: str | None = None) -> Markup:
    """A heading, ``<h1>`` by default.

    Parameters
    ----------
    text : str or markupsafe.Markup
        The heading's text (a ``str`` is escaped).
    level : int, optional
        1 to 6: ``<h1>`` to ``<h6>``.
    css : str, optional
        The heading's class.

    Returns
    -------
    markupsafe.Markup
        The heading element.
    """
    return element(f"h{int(level)}", text, inline=True, class_=css)


def paragraph(*content, css: str | None = None) -> Markup:
    """A paragraph of text and pieces (a formula, a link, code), run together.

    Parameters
    ----------
    *content : str or markupsafe.Markup or iterable or None
        The pieces, as for :func:`fragment`.
    css : str, optional
        The paragraph's class.

    Returns
    -------
    markupsafe.Markup
        The ``<p>`` element.
    """
    return element("p", *content, inline=True, class_=css)


def bullet_list(items, ordered: bool = False) -> Markup:
    """A list, one ``<li>`` per item.

    Parameters
    ----------
    items : iterable of str or markupsafe.Markup
        The items (a ``str`` is escaped).
    ordered : bool, optional
        ``<ol>`` rather than ``<ul>``.

    Returns
    -------
    markupsafe.Markup
        The list element.
    """
    return element("ol" if ordered else "ul", [element("li", item, inline=True) for item in items])


def section(title, *content, level: int = 2, css: str | None = None) -> Markup:
    """A ``<section>``: its heading (``css`` is the heading's class), then the content.

    Parameters
    ----------
    title : str or markupsafe.Markup
        The section's heading.
    *content : str or markupsafe.Markup or iterable or None
        What follows the heading, as for :func:`fragment`.
    level : int, optional
        The heading's level (``<h2>`` by default).
    css : str, optional
        The heading's class.

    Returns
    -------
    markupsafe.Markup
        The ``<section>`` element.
    """
    return element("section", heading(title, level, css), *content)


def table(rows, header=(), css: str | None = None) -> Markup:
    """A table of ``rows`` (each a sequence of cells: text or Markup), under an optional ``header`` row.

    Parameters
    ----------
    rows : iterable of sequence
        The rows, each a sequence of cells (``str``, escaped, or Markup).
    header : sequence, optional
        The header's cells, as ``<th>``; none by default.
    css : str, optional
        The table's class (``numbers`` right-aligns every column but the first).

    Returns
    -------
    markupsafe.Markup
        The ``<table>`` element.
    """
    lines = [element("tr", *(element("th", h, inline=True) for h in header), inline=True)] if header else []
    lines += [element("tr", *(element("td", cell, inline=True) for cell in row), inline=True) for row in rows]
    return element("table", lines, class_=css)


def pre(text, css: str | None = None) -> Markup:
    """Preformatted text (program output, a student's printout), escaped.

    Parameters
    ----------
    text : object
        The text (made a string, then escaped).
    css : str, optional
        The element's class (``input``, ``stderr``, ``error`` in :data:`STYLESHEET`).

    Returns
    -------
    markupsafe.Markup
        The ``<pre>`` element.
    """
    return element("pre", str(text), class_=css)


def code(text) -> Markup:
    """Inline code, escaped.

    Parameters
    ----------
    text : object
        The code (made a string, then escaped).

    Returns
    -------
    markupsafe.Markup
        The ``<code>`` element.
    """
    return element("code", str(text))


def link(href: str, text) -> Markup:
    """A link to a page beside this one, or to an http(s) page: no ``javascript:`` or ``data:`` link is made.

    Parameters
    ----------
    href : str
        A relative address, or one with the scheme ``http``, ``https`` or ``mailto``.
    text : str or markupsafe.Markup
        The link's text (a ``str`` is escaped).

    Returns
    -------
    markupsafe.Markup
        The ``<a>`` element.

    Raises
    ------
    ValueError
        If ``href`` has any other scheme.
    """
    scheme = SCHEME.match(href)
    if scheme and scheme.group(1).lower() not in ("http", "https", "mailto"):
        raise ValueError(f"not a link we write: {href!r}")
    return element("a", text, inline=True, href=href)


def figure(content, caption=None) -> Markup:
    """A figure with an optional caption.

    Parameters
    ----------
    content : str or markupsafe.Markup or iterable
        The figure (usually :func:`svg` or :func:`image`).
    caption : str or markupsafe.Markup, optional
        The ``<figcaption>``; none by default.

    Returns
    -------
    markupsafe.Markup
        The ``<figure>`` element.
    """
    return element("figure", content, None if caption is None else element("figcaption", caption, inline=True))


def svg(text: str) -> Markup:
    """An SVG drawing we made (matplotlib) as inline HTML, its XML prolog dropped.

    Trusted as HTML: pass only drawings of ours, whose labels matplotlib escaped (or drew as paths).

    Parameters
    ----------
    text : str
        The SVG file's text.

    Returns
    -------
    markupsafe.Markup
        The ``<svg>`` element and what follows it.

    Raises
    ------
    ValueError
        If ``text`` holds no ``<svg`` element.
    """
    start = text.find("<svg")
    if start < 0:
        raise ValueError("not an SVG drawing")
    return Markup(text[start:])


def image(data: bytes, mime: str = "image/png", alt: str = "") -> Markup:
    """An image embedded as a ``data:`` URI (no file beside the page, no request).

    Parameters
    ----------
    data : bytes
        The image file's bytes.
    mime : str, optional
        Its type: ``image/png``, ``image/jpeg``, ``image/gif`` or ``image/svg+xml``.
    alt : str, optional
        The text shown in its place (escaped).

    Returns
    -------
    markupsafe.Markup
        The ``<img>`` element.

    Raises
    ------
    ValueError
        If ``mime`` is any other type.
    """
    if mime not in ("image/png", "image/jpeg", "image/gif", "image/svg+xml"):
        raise ValueError(f"not an image type we embed: {mime!r}")
    return Markup('<img src="data:{};base64,{}" alt="{}">').format(mime, base64.b64encode(data).decode("ascii"), alt)


# ---------------------------------------------------------------------------- mathematics

# What latex2mathml writes, and what we let through: any other element or attribute (an ``href``
# or ``style`` from ``\href``/``\style``) makes the formula fail, or is dropped.
#: The MathML elements a formula may hold; any other makes :func:`math` show the LaTeX as code.
MATHML_TAGS = frozenset(
    "math mrow mi mn mo ms mtext mspace msub msup msubsup munder mover munderover mmultiscripts mprescripts none "
    "mfrac msqrt mroot mstyle merror mpadded mphantom menclose mtable mtr mtd mlabeledtr semantics annotation".split())
MATHML_ATTRIBUTES = frozenset(
    "display mathvariant mathsize mathcolor mathbackground stretchy fence separator largeop movablelimits accent "
    "accentunder form lspace rspace minsize maxsize symmetric width height depth voffset linethickness displaystyle "
    "scriptlevel columnspacing rowspacing columnalign rowalign columnlines rowlines frame framespacing notation "
    "linebreak equalrows equalcolumns".split())
# Environments latex2mathml lacks, written as the nearest one it has (same layout).
ENVIRONMENTS = {"aligned": "align*", "alignat": "align*", "alignat*": "align*", "gather": "align*",
                "gather*": "align*", "gathered": "align*"}


def math(latex: str, display: bool = False) -> Markup:
    """LaTeX as MathML, converted now (latex2mathml); ``display`` for a formula on its own line.

    LaTeX that cannot be converted is shown as code, with its ``$`` delimiters, and the page goes on.

    Parameters
    ----------
    latex : str
        The formula, without ``$`` delimiters.
    display : bool, optional
        A formula on its own line (``display="block"``) rather than in the text.

    Returns
    -------
    markupsafe.Markup
        The ``<math>`` element, or a ``<code class="math-error">`` holding the LaTeX.

    Examples
    --------
    >>> math("x^2")
    Markup('<math display="inline"><mrow><msup><mi>x</mi><mn>2</mn></msup></mrow></math>')
    """
    source = re.sub(r"\\(begin|end)\{(aligned|alignat\*?|gather\*?|gathered)\}",
                    lambda m: f"\\{m.group(1)}{{{ENVIRONMENTS[m.group(2)]}}}", str(latex))
    from latex2mathml.converter import convert_to_element

    try:
        return Markup(_serialised(convert_to_element(source, display="block" if display else "inline")))
    except Exception as error:  # any failure of the converter on odd LaTeX (its own errors, IndexError, recursion)
        delimiter = "$$" if display else "$"
        return Markup('<code class="math-error" title="not converted to MathML ({})">{}</code>').format(
            type(error).__name__, f"{delimiter}{latex}{delimiter}")


def _serialised(node) -> str:
    """The MathML tree as HTML: our own serialisation, every text escaped.

    latex2mathml's own string un-escapes everything it wrote (``\\text{<b>}`` would come out as a
    tag), so its tree is written here instead: entities it put into texts are decoded and the
    text escaped again; unknown elements raise, unknown attributes are left out.
    """
    if node.tag not in MATHML_TAGS:
        raise ValueError(f"unexpected MathML element {node.tag!r}")
    attributes = "".join(f' {name}="{html.escape(html.unescape(str(value)), quote=True)}"'
                         for name, value in node.attrib.items() if name in MATHML_ATTRIBUTES)
    inner = [_text(node.text)] + [_serialised(child) + _text(child.tail) for child in node]
    return f"<{node.tag}{attributes}>{''.join(inner)}</{node.tag}>"


def _text(text) -> str:
    return html.escape(html.unescape(text), quote=False) if text else ""


@functools.cache
def _markdown_parser():
    from nbconvert.filters.markdown_mistune import IPythonRenderer, MarkdownWithMath

    class MathMLRenderer(IPythonRenderer):
        """nbconvert's renderer (raw HTML escaped, no harmful link) with the maths as MathML."""

        def text(self, text: str) -> str:
            return _text(text)  # an entity (``&lt;``) shows as its character, as in Jupyter; never as markup

        def block_math(self, body: str) -> str:
            return math(body, display=True)

        def latex_environment(self, name: str, body: str) -> str:
            return math(f"\\begin{{{name}}}{body}\\end{{{name}}}", display=True)

        def inline_math(self, body: str) -> str:
            return math(body)

    renderer = MathMLRenderer(escape=True, allow_harmful_protocols=False, exclude_anchor_links=True)
    return MarkdownWithMath(renderer=renderer)


def markdown(text: str) -> Markup:
    """Markdown as Jupyter reads it (``$…$``, ``$$…$$``, ``\\begin{align*}``…), to HTML with MathML.

    Raw HTML in the text is escaped, links to ``javascript:`` are dropped, and code keeps its ``$``.

    Parameters
    ----------
    text : str
        The Markdown (a notebook's Markdown cell).

    Returns
    -------
    markupsafe.Markup
        The HTML.

    Examples
    --------
    >>> markdown("**F** = $m a$, <b>")
    Markup('<p><strong>F</strong> = <math display="inline"><mrow><mi>m</mi><mi>a</mi></mrow></math>, &lt;b&gt;</p>\\n')
    """
    return Markup(_markdown_parser().render(str(text)))


__all__ = ["MATHML_TAGS", "STYLESHEET", "bullet_list", "code", "element", "figure", "fragment", "heading", "image",
           "link", "markdown", "math", "page", "paragraph", "pre", "section", "svg", "table"]
