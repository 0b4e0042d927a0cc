# SPDX-License-Identifier: BSD-3-Clause
"""Every command example of README.md and docs/*.md works as written, run
from the files themselves (docexamples.py has the convention), and the
runner itself notices a broken example."""
import os
import tempfile
import unittest

from docexamples import DOCUMENTS, ROOT, read_blocks, run_document


class Documents(unittest.TestCase):
    def test_every_document_has_runnable_examples_or_none_to_run(self):
        """The documents the suite walks: README.md and every docs/*.md."""
        self.assertIn("README.md", DOCUMENTS)
        self.assertIn(os.path.join("docs", "simctl.md"), DOCUMENTS)
        runnable = [d for d in DOCUMENTS if any(b.runs for b in read_blocks(d))]
        self.assertGreaterEqual(len(runnable), 6, runnable)


class QuickStart(unittest.TestCase):
    """README.md opens with the first ten minutes of a newcomer: run it, open
    the page, connect a client, run a driver's test. Every step but the
    first (which is `make run` itself) is an example the suite runs, so the
    quick start works when pasted (test_README_md runs them)."""

    def test_the_readme_starts_with_the_four_steps(self):
        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            text = f.read()
        sections = [line for line in text.splitlines() if line.startswith("## ")]
        self.assertEqual(sections[:2], ["## The first ten minutes", "## The two commands"])
        quick = text.split("## The first ten minutes", 1)[1].split("\n## ", 1)[0]
        steps = ["**1. Run it.**", "**2. Open the page**", "**3. Connect a client.**",
                 "**4. Run a driver's test.**"]
        self.assertEqual([step for step in steps if step in quick], steps)
        end = text[:text.index("## The two commands")].count("\n")  # its last line
        blocks = [b for b in read_blocks("README.md") if b.line < end]
        runs = [b.text for b in blocks if b.runs]
        self.assertTrue(any("curl" in t and "8080" in t for t in runs), "the page, fetched")
        self.assertTrue(any("nc localhost 1000" in t for t in runs), "a GCL client")
        self.assertTrue(any("pytest" in t and "wsgsim.pytest_plugin" in t for t in runs),
                        "a driver's test")
        self.assertTrue(all(b.output is not None for b in blocks if b.runs),
                        "each step shows what it prints")
        self.assertIn("make run", [b.text.strip() for b in blocks if b.kind == "sh"])


def add_document_test(document):
    def test(self):
        failures = run_document(document)
        self.assertEqual(failures, [], "\n\n" + "\n\n".join(failures))
    name = "test_" + document.replace(os.sep, "_").replace(".", "_").replace("-", "_")
    test.__name__ = name
    test.__doc__ = "The examples of %s work when pasted in order." % document
    setattr(Documents, name, test)


for _document in DOCUMENTS:
    add_document_test(_document)


class Runner(unittest.TestCase):
    """The runner fails where a reader's paste would."""

    def document(self, text):
        fd, path = tempfile.mkstemp(suffix=".md", dir=os.path.join(ROOT, "build"))
        with os.fdopen(fd, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)
        return path

    def failures(self, text):
        return run_document(self.document(text))

    def test_a_command_in_an_unmarked_block_is_reported(self):
        for fence in ("```", "```text"):
            failures = self.failures("%s\ncurl localhost:8080/api/devices\n```\n" % fence)
            self.assertEqual(len(failures), 1, failures)
        self.assertIn("fence kind ''", self.failures("```\ncurl x\n```\n")[0])

    def test_a_failing_command_fails(self):
        failures = self.failures("```sh\necho one\nfalse\necho never\n```\n")
        self.assertEqual(len(failures), 1, failures)
        self.assertIn("`false` exited with 1", failures[0])

    def test_output_is_compared(self):
        self.assertEqual(self.failures("```sh\necho one; echo two\n```\n\n"
                                       "```output\no…\n…\n```\n"), [])
        failures = self.failures("```sh\necho one\n```\n\n```output\ntwo\n```\n")
        self.assertEqual(len(failures), 1, failures)
        self.assertIn("the output differs", failures[0])

    def test_a_transcript_that_differs_fails(self):
        self.assertEqual(self.failures("```transcript server\n> POS?\n< POS=55.0\n```\n"), [])
        failures = self.failures("```transcript server\n> MOVE(20)\n< ACK MOVE\n```\n")
        self.assertEqual(len(failures), 1, failures)
        self.assertIn("got:      < ERR MOVE 3", failures[0])

    def test_a_server_that_does_not_start_fails(self):
        failures = self.failures("```sh serves\nbuild/wsgsim --model 'WSG 99-999'\n```\n")
        self.assertEqual(len(failures), 1, failures)
        self.assertIn("ended before it was ready", failures[0])


if __name__ == "__main__":
    unittest.main()
