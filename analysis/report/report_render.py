"""The report's text from its blocks: Markdown (report.md) and HTML (report.html).

A block is (kind, *args): ("h1"|"h2", text), ("p", text), ("ul", [items]), ("table", head,
rows) or ("img", caption, file name); analysis.report.report builds them."""
import html

# One symbol per verdict, so that a reader sees them at a glance (and the HTML's colours).
SYMBOLS = {"reproduced within error bars": "✓", "reproduced qualitatively": "≈", "not reproduced": "✗",
           "inconclusive": "?"}


def markdown(blocks):
    out = []
    for kind, *a in blocks:
        if kind in ("h1", "h2"):
            out.append(("#" if kind == "h1" else "##") + f" {a[0]}\n")
        elif kind == "p":
            out.append(a[0] + "\n")
        elif kind == "ul":
            out.append("".join(f"- {x}\n" for x in a[0]))
        elif kind == "table":
            head, body = a
            cell = lambda s: str(s).replace("|", "\\|")
            out.append("| " + " | ".join(map(cell, head)) + " |\n|" + "---|" * len(head) + "\n"
                       + "".join("| " + " | ".join(map(cell, r)) + " |\n" for r in body))
        elif kind == "img":
            out.append(f"![{a[0]}]({a[1]})\n\n*{a[0]}*\n")
    return "\n".join(out)


def _td(cell):
    """A table cell; a verdict cell (it starts with its symbol) gets its colour class."""
    text = str(cell)
    cls = f" class='v{text[0]}'" if text[:1] in SYMBOLS.values() else ""
    return f"<td{cls}>{html.escape(text)}</td>"


def to_html(blocks):
    e = html.escape
    out = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>granudrag report</title>"
           "<style>body{font-family:sans-serif;max-width:60em;margin:auto}table{border-collapse:"
           "collapse}td,th{border:1px solid #999;padding:2px 6px}img{max-width:100%}"
           ".v✓{background:#cdeccd}.v≈{background:#eeeebb}.v✗{background:#f3c6c6}.v\\?{background:#e2e2e2}"
           "</style>"
           "</head><body>"]
    for kind, *a in blocks:
        if kind in ("h1", "h2"):
            out.append(f"<{kind}>{e(a[0])}</{kind}>")
        elif kind == "p":
            out.append(f"<p>{e(a[0])}</p>")
        elif kind == "ul":
            out.append("<ul>" + "".join(f"<li>{e(x)}</li>" for x in a[0]) + "</ul>")
        elif kind == "table":
            head, body = a
            out.append("<table><tr>" + "".join(f"<th>{e(str(h))}</th>" for h in head) + "</tr>"
                       + "".join("<tr>" + "".join(_td(c) for c in r) + "</tr>" for r in body)
                       + "</table>")
        elif kind == "img":
            out.append(f"<figure><img src='{e(a[1])}' alt='{e(a[0])}'>"
                       f"<figcaption>{e(a[0])}</figcaption></figure>")
    return "\n".join(out + ["</body></html>"])
