"""Build a notebook from a python file with '# %%' cells ('# %% [markdown]' for text,
'# %% tags=["parameters"]' for the papermill parameters cell)."""
import re
import sys

import nbformat
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

src, dst = sys.argv[1], sys.argv[2]
text = open(src).read()
cells = []
for chunk in re.split(r'^# %%', text, flags=re.M)[1:]:
    header, _, body = chunk.partition('\n')
    body = body.strip('\n')
    if '[markdown]' in header:
        lines = [l[2:] if l.startswith('# ') else l.lstrip('#') for l in body.splitlines()]
        cells.append(new_markdown_cell('\n'.join(lines)))
    else:
        c = new_code_cell(body)
        if 'parameters' in header:
            c.metadata['tags'] = ['parameters']
        cells.append(c)
nb = new_notebook(cells=cells, metadata={
    "kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"},
    "language_info": {"name": "python"}})
nbformat.write(nb, dst)
