"""results/REPORT.html: REPORT.md as a web page, with each experiment's runs playing in the 3D
viewer beside its PNGs.

- make_views: for every experiment that left run folders (<name>/runs/order.txt lists them,
  experiments/common.h write_run_folder), `physik view` writes <name>/view.html, one
  self-contained page (three.js inlined) overlaying the runs; runs of another rig (the contacts
  experiment's 1,000-bone coils beside pinhead) go to view-2.html, view-3.html, ..., and a long
  rig's runs are decimated to BONE_FRAMES bone-frames;
- to_html: the markdown analysis/report.py writes (headings, tables, bullets, images, links,
  `code`, **bold**: the subset it uses) as HTML. Every text is escaped first (html.escape), so
  names from user files stay text; a link is made only to a relative path or an http(s) URL.
  A row of images whose experiment has a view.html gets the viewer beside it, in an iframe of
  that page; the animated GIF, the markdown's stand-in for the viewer, is left out there.
"""
import html
import json
import os
import re
import subprocess

STYLE = """
body { font: 15px/1.45 system-ui, sans-serif; max-width: 1500px; margin: 16px auto; padding: 0 16px;
  color: #222; }
table { border-collapse: collapse; margin: 8px 0 14px; font-size: 13px; }
td, th { border: 1px solid #ccc; padding: 3px 6px; vertical-align: top; text-align: left; }
th { background: #f3f4f6; }
code { background: #f3f4f6; padding: 0 3px; border-radius: 3px; }
.figures { display: flex; flex-wrap: wrap; gap: 12px; align-items: flex-start; }
.figures .pngs { flex: 1 1 520px; }
.figures .pngs img { max-width: 100%; display: block; margin-bottom: 8px; }
.figures iframe { flex: 1 1 620px; height: 900px; border: 1px solid #ddd; }
"""


def run_folders(results, name):
    """The run folders an experiment left, in the order it wrote them."""
    path = os.path.join(results, name, "runs", "order.txt")
    if not os.path.isfile(path):
        return []
    with open(path) as f:
        names = [line.strip() for line in f if line.strip()]
    return [os.path.join(results, name, "runs", n) for n in names]


# bone-frames kept per run in a report's page (`physik view --max-frames` = this over the bones,
# at most its default 10,000 frames): a 1,000-bone run keeps 60 frames, about 10 MB
BONE_FRAMES = 60000


def rig_key(folder):
    """The bones (name, parent) of a run folder's rig: runs with the same key can be overlaid."""
    with open(os.path.join(folder, "scene.json")) as f:
        bones = json.load(f)["rig"]["bones"]
    return tuple((b["name"], b.get("parent", "")) for b in bones)


def view_groups(folders):
    """The folders grouped by rig, each group in the order written, groups by first appearance:
    `physik view` overlays only runs of the same bones."""
    groups = {}
    for folder in folders:
        groups.setdefault(rig_key(folder), []).append(folder)
    return list(groups.values())


def view_pages(results, name):
    """The viewer pages of an experiment, as make_views names them: view.html for the runs of its
    first rig, view-2.html, view-3.html, ... for the others."""
    pages = []
    for k in range(1, 100):
        page = os.path.join(name, "view.html" if k == 1 else "view-%d.html" % k)
        if not os.path.isfile(os.path.join(results, page)):
            break
        pages.append(page)
    return pages


def make_views(results, sections, physik):
    """<name>/view.html (and view-2.html, ... for runs of other rigs) for every experiment with
    run folders; {page: size in bytes}."""
    sizes = {}
    for name, _, rep in sections:
        folders = run_folders(results, name)
        for k, group in enumerate(view_groups(folders) if folders else [], start=1):
            page = os.path.join(name, "view.html" if k == 1 else "view-%d.html" % k)
            out = os.path.join(results, page)
            frames = max(50, min(10000, BONE_FRAMES // len(rig_key(group[0]))))
            subprocess.run([physik, "view"] + group + ["--out", out, "--title",
                                                      rep.get("title", name),
                                                      "--max-frames", str(frames)], check=True)
            sizes[page] = os.path.getsize(out)
    return sizes


LINK = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")
SCHEME = re.compile(r"^(?!https?:)[A-Za-z][A-Za-z0-9+.-]*:")  # javascript:, data: stay text


def inline(text):
    """One line of markdown text as HTML: escaped, then `code`, [text](href) and **bold**."""
    out = html.escape(text, quote=True)
    out = re.sub(r"`([^`]+)`", r"<code>\1</code>", out)
    out = LINK.sub(lambda m: m.group(0) if SCHEME.match(m.group(2)) else
                   '<a href="%s">%s</a>' % (m.group(2), m.group(1)), out)
    return re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", out)


def table_html(lines):
    """Markdown table lines (header, separator, rows) as an HTML table."""
    def cells(line):
        return [c.strip() for c in line.strip().strip("|").split("|")]
    head = "".join("<th>%s</th>" % inline(c) for c in cells(lines[0]))
    out = ["<table>", "<tr>" + head + "</tr>"]
    for line in lines[2:]:
        out.append("<tr>" + "".join("<td>%s</td>" % inline(c) for c in cells(line)) + "</tr>")
    return out + ["</table>"]


IMAGE = re.compile(r"^!\[([^\]]*)\]\(([^)\s]+)\)$")


def figures_html(lines, results):
    """A run of image lines: the PNGs, and the viewer of their experiment beside them."""
    images = [IMAGE.match(line).groups() for line in lines]
    folder = images[0][1].split("/")[0]
    view = os.path.join(folder, "view.html")
    has_view = results is not None and os.path.isfile(os.path.join(results, view))
    pngs = ['<img src="%s" alt="%s">' % (html.escape(src, True), html.escape(alt, True))
            for alt, src in images if not (has_view and src.endswith(".gif"))]
    out = ['<div class="figures">', '<div class="pngs">'] + pngs + ["</div>"]
    if has_view:
        out.append('<iframe src="%s" loading="lazy" title="%s"></iframe>'
                   % (html.escape(view, True), html.escape("3D viewer: " + folder, True)))
    return out + ["</div>"]


def blocks(md):
    """The markdown's lines grouped: (kind, lines) with kind table, images, bullets, heading or
    text. An indented line continues the bullets above it (a wrapped bullet, or a bullet under a
    bullet: analysis/report.py wraps at WRAP); consecutive text lines are one paragraph."""
    out = []
    for line in md.splitlines():
        kind = ("blank" if not line.strip() else "heading" if line.startswith("#")
                else "table" if line.startswith("|") else "images" if IMAGE.match(line)
                else "bullets" if line.startswith("- ") else "text")
        if kind == "text" and line[:1].isspace() and out and out[-1][0] == "bullets":
            kind = "bullets"
        if out and out[-1][0] == kind and kind in ("table", "images", "bullets", "text"):
            out[-1][1].append(line)
        else:
            out.append((kind, [line]))
    return out


def bullets_html(lines):
    """Bullet lines as nested lists: "- " an item, "  - " an item under it, any other indented
    line the text of the item above it, continued."""
    items = []  # [text, [sub-item texts]]
    for line in lines:
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if indent == 0 and stripped.startswith("- "):
            items.append([stripped[2:], []])
        elif stripped.startswith("- ") and items:
            items[-1][1].append(stripped[2:])
        elif items and items[-1][1] and indent > 2:
            items[-1][1][-1] += " " + stripped
        elif items:
            items[-1][0] += " " + stripped
    out = ["<ul>"]
    for text, subs in items:
        inner = "".join("<li>%s</li>" % inline(s) for s in subs)
        out.append("<li>%s%s</li>" % (inline(text), "<ul>%s</ul>" % inner if subs else ""))
    return out + ["</ul>"]


def to_html(md, results=None, title="PhysIK reproduction report"):
    """The report's markdown as a whole HTML page."""
    body = []
    for kind, lines in blocks(md):
        if kind == "heading":
            level = len(lines[0]) - len(lines[0].lstrip("#"))
            body.append("<h%d>%s</h%d>" % (level, inline(lines[0][level:].strip()), level))
        elif kind == "table":
            body += table_html(lines)
        elif kind == "images":
            body += figures_html(lines, results)
        elif kind == "bullets":
            body += bullets_html(lines)
        elif kind == "text":
            body.append("<p>%s</p>" % inline(" ".join(l.strip() for l in lines)))
    return "\n".join(['<!DOCTYPE html>', '<html lang="en">', "<head>", '<meta charset="utf-8">',
                      "<title>%s</title>" % html.escape(title), "<style>%s</style>" % STYLE,
                      "</head>", "<body>"] + body + ["</body>", "</html>", ""])
