"""The paper's figures (PNG + PDF, with the data each plots), one function per figure, and the list that draws them."""
