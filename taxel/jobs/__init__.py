"""Jobs: whole runs built on the API (taxel.api) and the analyses, above the
reports and below the command line. main_job: `taxel demo` (`make demo`);
thesis_ch4: the model side of thesis chapter 4."""
