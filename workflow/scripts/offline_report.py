"""`snakemake --report` without internet access (Snakemake 7.21 downloads the report's
JavaScript, CSS and licence texts while writing it: snakemake/snakemake#282).

Runs Snakemake's own --report with those downloads replaced by empty text: the report
lists every result and figure with its caption and provenance, but its page needs the
network to load its scripts when opened. With internet access use `snakemake --report`.

    /usr/bin/python3 workflow/scripts/offline_report.py [snakemake arguments] --report out.html
"""
import sys

import snakemake
import snakemake.report
import snakemake.report.data.common as common
import snakemake.report.data.packages as packages

_get = common.get_resource_as_string


def _local_only(path_or_uri):
    return _get(path_or_uri) if common.is_local_file(path_or_uri) else ""


for module in (common, packages, snakemake.report):
    if hasattr(module, "get_resource_as_string"):
        module.get_resource_as_string = _local_only

if __name__ == "__main__":
    snakemake.main(sys.argv[1:])
