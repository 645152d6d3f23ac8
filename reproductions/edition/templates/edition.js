(function(){
  // the filters: each names a data attribute of the cards (rows and measurements) or of the findings; their state
  // lives in the address (?verdict=differs&reason=ocr) so that a filtered view can be linked and reloaded
  var box=document.getElementById('filters');box.hidden=false;
  var names=['part','verdict','reason','section','category'];
  var sel={};names.forEach(function(k){sel[k]=document.getElementById('f-'+k);});
  var cards=document.querySelectorAll('article.row, article.measure');
  var findings=document.querySelectorAll('#findings li[data-category]');
  var shown=document.getElementById('f-shown');
  function apply(){var n=0,m=0;
    cards.forEach(function(r){var ok=true;
      ['part','verdict','reason','section'].forEach(function(k){var v=sel[k].value;if(v&&r.dataset[k]!==v){ok=false;}});
      r.hidden=!ok;if(ok){n++;}});
    findings.forEach(function(f){var v=sel.category.value;f.hidden=!!v&&f.dataset.category!==v;if(!f.hidden){m++;}});
    if(sel.category.value){var d=document.getElementById('more-findings');if(d){d.open=true;}}
    document.querySelectorAll('section.experiment, section.measured-experiment').forEach(function(s){
      var any=!!s.querySelector('article:not([hidden])');s.querySelector('.none').hidden=any;
      s.querySelectorAll('figure, .rows-heading').forEach(function(e){e.hidden=!any;});});
    shown.textContent=n+' of '+cards.length+' rows and '+m+' of '+findings.length+' findings shown';
    var q=new URLSearchParams();names.forEach(function(k){if(sel[k].value){q.set(k,sel[k].value);}});
    var s=q.toString();
    try{history.replaceState(null,'',(s?'?'+s:location.pathname.split('/').pop())+location.hash);}catch(e){}}
  var start=new URLSearchParams(location.search);
  names.forEach(function(k){var v=start.get(k);
    if(v&&Array.prototype.some.call(sel[k].options,function(o){return o.value===v;})){sel[k].value=v;}
    sel[k].addEventListener('change',apply);});
  document.addEventListener('click',function(e){
    var a=e.target.closest('a[href^="#"]');if(!a){return;}
    var t=document.getElementById(decodeURIComponent(a.getAttribute('href').slice(1)));
    if(t&&t.closest('[hidden]')){names.forEach(function(k){sel[k].value='';});apply();}});
  apply();
})();
