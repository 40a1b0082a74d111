"""The README's Python example is executed as written (the Rust one runs as a doctest), its
headline figures are those of the benchmark's report in docs/benchmark.md, and the links of
the README and of each document in docs/, within it or to another, reach their headings."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_examples_run():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "the README lost its Python example"
    for block in blocks:
        exec(compile(block, str(README), "exec"), {})


BENCHMARK = README.parent / "docs" / "benchmark.md"


def test_the_readme_s_headline_figures_are_the_benchmark_report_s():
    # The README quotes the report split's headline (docs/benchmark.md, "The report split"): the
    # two are written by hand from the same run, and a run written into one must reach the other.
    report = BENCHMARK.read_text().split("## The report split", 1)[1]
    headline = " ".join(report.split("### Headline", 1)[1].split("### ", 1)[0].split())
    readme = " ".join(README.read_text().split())
    found = re.search(
        r"Torso estimates for ([\d.]+) % .*? in ([\d.]+) % of them \(90 % interval ([\d.]+) % to "
        r"([\d.]+) % .*?\), ([\d.]+) % in the worst view bin .*?; ([\d.]+) % of the ([\d.]+) % "
        r"whose heading .*? azimuth error median ([\d.]+),",
        headline,
    )
    assert found, "the report's headline sentence changed its wording: update this test"
    estimated, flips, low, high, worst, confident_flips, confident, median = found.groups()
    for quoted in (
        f"Torso estimates for {estimated} % of the person-frames in view, azimuth error median {median}",
        f"in {flips} % of them (90 % interval {low} to {high} %",
        f"{worst} % in the worst 45-degree view bin",
        f"{confident} % of them, and those flip in {confident_flips} %",
    ):
        assert quoted in readme, quoted
    # The forecasts' medians: the README's cells are torsocast / hold / constant velocity.
    method = {"torsocast": 0, "hold the estimate": 1, "constant velocity": 2}
    expected: dict[str, list[list[str]]] = {}
    cell = r"\| ([\d.]+) "
    for component, name, *medians in re.findall(
        rf"\| (\w+ \((?:cm|deg)\)), ({'|'.join(method)}) {cell * 3}\|", headline
    ):
        columns = expected.setdefault(component, [["", "", ""] for _ in medians])
        for horizon, value in enumerate(medians):
            columns[horizon][method[name]] = value
    triple = r"\| ([\d.]+) / ([\d.]+) / ([\d.]+) "
    quoted_rows = {
        component: [list(values[3 * h : 3 * h + 3]) for h in range(3)]
        for component, *values in re.findall(rf"\| (\w+ \((?:cm|deg)\)) {triple * 3}\|", readme)
    }
    assert set(expected) == {"centre (cm)", "azimuth (deg)", "elevation (deg)"}
    assert quoted_rows == expected
    # The flips by distance: the 1-2 m band, the range beyond 2 m, and the near band's confidence.
    distance = report.split("#### By distance", 1)[1].split("####", 1)[0]
    bands = {
        band: (flips, share, confident_flips)
        for band, flips, share, confident_flips in re.findall(
            r"\| ([\w -]+) \| \d+ \| [\d.]+ % \| ([\d.]+) % \| ([\d.]+) % / ([\d.]+) % \|", distance
        )
    }
    near = bands["1-2 m"]
    beyond = sorted((bands[b][0] for b in ("2-3 m", "3-4 m", "4 m and more")), key=float)
    assert (
        f"{near[0]} % of those 1 to 2 m from the camera" in readme
        and f"({beyond[0]} to {beyond[-1]} % beyond 2 m; only {near[1]} % of the near ones are confident, "
        f"below, and those flip in {near[2]} %)"
        in readme
    )


def _anchor(heading: str) -> str:
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def _anchors(doc: Path) -> set[str]:
    return {_anchor(h) for h in re.findall(r"^#+ (.+)$", doc.read_text(), flags=re.M)}


DOCUMENTS = [README, *sorted((README.parent / "docs").glob("*.md"))]


def test_every_link_within_a_document_reaches_one_of_its_headings():
    # docs/benchmark_log.md's topic index links some seventy sections by their anchors; a
    # section renamed leaves a link that goes nowhere.
    for doc in DOCUMENTS:
        links = re.findall(r"\]\(#([^)]+)\)", doc.read_text())
        missing = [link for link in links if link not in _anchors(doc)]
        assert not missing, f"{doc.name}: links to no heading: {missing}"


def test_every_link_to_another_document_reaches_it_and_its_heading():
    # The benchmark's page and its log link each other's sections.
    for doc in DOCUMENTS:
        for target, anchor in re.findall(r"\]\(([\w./-]+\.md)(?:#([^)]+))?\)", doc.read_text()):
            path = doc.parent / target
            assert path.is_file(), f"{doc.name}: links to {target}, which is not there"
            assert not anchor or anchor in _anchors(path), f"{doc.name}: {target}#{anchor} is no heading"
